//! The three closures of a solve, built once from the trained models and their training
//! data (docs/physics.md section 8), and where a solved profile lies relative to each
//! closure's training rows. The command line and the Python package both solve through
//! this.
use crate::closure::{Closure, LearnedClosure, NonlocalClosure};
use crate::error::{Result, SolverError};
use crate::local_fit::fit_local_rheology;
use crate::solution::ProfileSolution;
use crate::theta_balance::{ThetaBalance, ThetaBalanceFit};
use ndarray::Array2;
use schema::columns as col;
use schema::Observable;
use std::path::Path;
use surrogate::{Dataset, DomainCheck, LocalRheology, Mapping, Predictor, Samples, TrainingDomain};

/// Which closure a solve uses (its discriminant indexes [`ClosureKind::ALL`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClosureKind {
    /// The trained `dv` mapping, (J, Delta_v, phi) -> (phi_loc, mu).
    Learned,
    /// mu = A J^b and phi_loc by eq 6.7, fitted on the training data.
    Local,
    /// The trained `theta` mapping, (J, Theta, phi) -> (phi_loc, mu), with Theta from its
    /// balance l^2 Theta'' = Theta - c J^beta fitted on the training data.
    Nonlocal,
}

impl ClosureKind {
    pub const ALL: [ClosureKind; 3] = [
        ClosureKind::Learned,
        ClosureKind::Local,
        ClosureKind::Nonlocal,
    ];

    pub fn name(self) -> &'static str {
        match self {
            ClosureKind::Learned => "learned",
            ClosureKind::Local => "local",
            ClosureKind::Nonlocal => "nonlocal",
        }
    }

    /// The closure called `name`.
    pub fn from_name(name: &str) -> Result<ClosureKind> {
        ClosureKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| {
                SolverError::InvalidArgument(format!(
                    "unknown closure `{name}` (learned, local or nonlocal)"
                ))
            })
    }
}

/// The closures, their training domains and the fitted Theta balance.
pub struct Closures {
    pub learned: LearnedClosure,
    pub local: LocalRheology,
    pub nonlocal: NonlocalClosure,
    pub theta_fit: ThetaBalanceFit,
    /// Each closure's training domain and its features, in the order of
    /// [`ClosureKind::ALL`].
    domains: Vec<(TrainingDomain, Vec<String>)>,
}

impl Closures {
    /// The closures of the `dv` and `theta` models in `models`, with the local law, its
    /// training domain and the Theta balance fitted on `train` (by default the `dv` model's
    /// training data, the file its sidecar names, found from the models' folder as
    /// [`surrogate::ModelMeta::training_file`] says, whatever the current directory). Every
    /// closure needs it: the local law is the local closure and the start of the learned and
    /// nonlocal closures' continuation, the Theta balance the nonlocal closure's.
    pub fn load(models: &Path, train: Option<&Path>) -> Result<Closures> {
        let dv = Predictor::load(models, "dv")?;
        let train = train
            .map(Path::to_path_buf)
            .unwrap_or_else(|| dv.meta().training_file(models));
        let train_data = Dataset::read_csv(&train)?;
        let theta_fit = ThetaBalance::fit(&train_data)?;
        let theta = Predictor::load(models, "theta")?;
        let dv_features = dv.meta().features.clone();
        // The local law is fitted on the training rows: its domain is theirs.
        let local_domain = TrainingDomain::fit(&Samples::from_dataset(
            &train_data,
            Mapping::by_name("dv")?,
        )?)?;
        let domains = vec![
            (dv.domain().clone(), dv_features.clone()),
            (local_domain, dv_features),
            (theta.domain().clone(), theta.meta().features.clone()),
        ];
        Ok(Closures {
            learned: LearnedClosure::new(dv)?,
            local: fit_local_rheology(&train_data)?,
            nonlocal: NonlocalClosure::new(theta, theta_fit.balance)?,
            theta_fit,
            domains,
        })
    }

    /// The closure of `kind`.
    pub fn get(&self, kind: ClosureKind) -> &dyn Closure {
        match kind {
            ClosureKind::Learned => &self.learned,
            ClosureKind::Local => &self.local,
            ClosureKind::Nonlocal => &self.nonlocal,
        }
    }

    /// Where each bin of `s` lies relative to the training rows of the closure `kind`, in
    /// that closure's features: J and Delta_v or Theta of the solution, the scene's `phi`.
    /// The learned closures' domains are their models' own; the local closure's is fitted on
    /// its training rows.
    pub fn domain_checks(
        &self,
        kind: ClosureKind,
        phi: f64,
        s: &ProfileSolution,
    ) -> Result<Vec<DomainCheck>> {
        let (domain, features) = &self.domains[kind as usize];
        let columns = features
            .iter()
            .map(
                |name| match Observable::from_name(name).and_then(|o| s.column(o)) {
                    Some(values) => Ok(values.to_vec()),
                    None if name == col::PHI => Ok(vec![phi; s.j.len()]),
                    None => Err(SolverError::InvalidArgument(format!(
                        "a solve gives no `{name}` per bin for the training-domain check"
                    ))),
                },
            )
            .collect::<Result<Vec<_>>>()?;
        let rows = Array2::from_shape_fn((s.j.len(), columns.len()), |(k, f)| columns[f][k]);
        Ok(domain.check(rows.view())?)
    }
}
