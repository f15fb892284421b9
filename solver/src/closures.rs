//! The closures of a solve, built once from the trained models and their training data
//! (docs/physics.md section 8), and where a solved profile lies relative to each closure's
//! training rows. The command line and the Python package both solve through this.
use crate::bands::{BandCalibration, ProfileBands};
use crate::closure::{Closure, ExtremumClosure, LearnedClosure, NonlocalClosure};
use crate::closure_kind::ClosureKind;
use crate::error::{Result, SolverError};
use crate::local_fit::fit_local_rheology;
use crate::problem::ProfileProblem;
use crate::solution::ProfileSolution;
use crate::solved_profile::BandSummary;
use crate::theta_balance::{ThetaBalance, ThetaBalanceFit};
use ndarray::Array2;
use schema::columns as col;
use schema::Observable;
use std::path::Path;
use surrogate::{
    Dataset, DomainCheck, LocalRheology, Mapping, ModelMeta, Predictor, Samples, TrainingDomain,
    DEFAULT_LEVEL,
};

/// The closures, their training domains, the fitted Theta balance and the calibration of the
/// bands of their solves.
pub struct Closures {
    pub learned: LearnedClosure,
    pub local: LocalRheology,
    pub nonlocal: NonlocalClosure,
    /// `None` when the models' folder has no `ext` model (trained before it existed).
    pub extremum: Option<ExtremumClosure>,
    pub theta_fit: ThetaBalanceFit,
    /// Each closure's training domain and its features, in the order of
    /// [`ClosureKind::ALL`].
    domains: Vec<(TrainingDomain, Vec<String>)>,
    /// The sidecars of the trained mappings (`dv`, `theta`, `ext` if present).
    metas: Vec<ModelMeta>,
    /// The models' `bands.json`, if they have one.
    pub band_calibration: Option<BandCalibration>,
}

/// The bands of one solve, or why there are none.
pub enum Bands {
    Calibrated(Box<(ProfileBands, BandSummary)>),
    Missing(String),
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
        let ext = match Predictor::load(models, "ext") {
            Ok(ext) => Some(ext),
            Err(surrogate::SurrogateError::Io { source, .. })
                if source.kind() == std::io::ErrorKind::NotFound =>
            {
                None
            }
            Err(e) => return Err(e.into()),
        };
        let metas: Vec<ModelMeta> = [Some(&dv), Some(&theta), ext.as_ref()]
            .into_iter()
            .flatten()
            .map(|p| p.meta().clone())
            .collect();
        let mut domains = vec![
            (dv.domain().clone(), dv_features.clone()),
            (local_domain, dv_features),
            (theta.domain().clone(), theta.meta().features.clone()),
        ];
        if let Some(ext) = &ext {
            domains.push((ext.domain().clone(), ext.meta().features.clone()));
        }
        Ok(Closures {
            learned: LearnedClosure::new(dv)?,
            local: fit_local_rheology(&train_data)?,
            nonlocal: NonlocalClosure::new(theta, theta_fit.balance)?,
            extremum: ext.map(ExtremumClosure::new).transpose()?,
            theta_fit,
            domains,
            metas,
            band_calibration: BandCalibration::load(models)?,
        })
    }

    /// The bands at `level` of the solution `s` of `problem` with closure `kind`: each bin's
    /// scale ([`ProfileProblem::band_scales`]) times the margin of the models' calibration;
    /// [`Bands::Missing`] with the reason when the models have no calibration for it.
    pub fn bands(
        &self,
        kind: ClosureKind,
        problem: &ProfileProblem,
        s: &ProfileSolution,
        level: f64,
    ) -> Result<Bands> {
        let Some(calibration) = &self.band_calibration else {
            return Ok(Bands::Missing(
                "the models have no bands.json (train writes it when it trains dv and theta \
                 together)"
                    .to_owned(),
            ));
        };
        let mapping = kind.mapping().unwrap_or("dv");
        if let Some(meta) = self.metas.iter().find(|m| m.mapping == mapping) {
            if let Some(why) = calibration.mismatch(meta) {
                return Ok(Bands::Missing(why));
            }
        }
        let (Some(margins), Some(record)) = (
            calibration.margins(kind.name(), level)?,
            calibration
                .closures
                .iter()
                .find(|c| c.closure == kind.name()),
        ) else {
            return Ok(Bands::Missing(format!(
                "bands.json has no calibration of the {} closure",
                kind.name()
            )));
        };
        let scales = problem.band_scales(self.get(kind)?, s, DEFAULT_LEVEL)?;
        let bands = ProfileBands::new(s, &scales, margins, level);
        let summary = BandSummary {
            level,
            margins,
            relative_widths: bands.relative_widths(s),
            held_out_coverage: record.fold_coverage,
        };
        Ok(Bands::Calibrated(Box::new((bands, summary))))
    }

    /// The closure of `kind`; an error for the extremum closure when the models' folder has
    /// no `ext` model.
    pub fn get(&self, kind: ClosureKind) -> Result<&dyn Closure> {
        Ok(match kind {
            ClosureKind::Learned => &self.learned,
            ClosureKind::Local => &self.local,
            ClosureKind::Nonlocal => &self.nonlocal,
            ClosureKind::Extremum => self.extremum.as_ref().ok_or_else(|| {
                SolverError::InvalidArgument(
                    "the extremum closure needs the `ext` model, which the models' folder \
                     lacks (trained before it existed): train again"
                        .to_owned(),
                )
            })?,
        })
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
        let rows = self.closure_features(kind, phi, s)?;
        Ok(self.domains[kind as usize].0.check(rows.view())?)
    }

    /// Each bin of `s` in the coordinates of the closure `kind`'s training domain (one
    /// `Vec` per bin), and that domain's distance threshold: within it, two states are as
    /// close as a training simulation's bins to the nearest other simulation's.
    pub fn domain_coordinates(
        &self,
        kind: ClosureKind,
        phi: f64,
        s: &ProfileSolution,
    ) -> Result<(Vec<Vec<f64>>, f64)> {
        let rows = self.closure_features(kind, phi, s)?;
        let domain = &self.domains[kind as usize].0;
        let flat = domain.coordinates(rows.view())?;
        let bins = flat
            .chunks(rows.ncols().max(1))
            .map(<[f64]>::to_vec)
            .collect();
        Ok((bins, domain.threshold))
    }

    /// The features of the closure `kind` at each bin of `s` (bins x features).
    fn closure_features(
        &self,
        kind: ClosureKind,
        phi: f64,
        s: &ProfileSolution,
    ) -> Result<Array2<f64>> {
        self.get(kind)?;
        let (_, features) = &self.domains[kind as usize];
        let columns = features
            .iter()
            .map(
                |name| match Observable::from_name(name).and_then(|o| s.column(o)) {
                    Some(values) => Ok(values.to_vec()),
                    None if name == col::PHI => Ok(vec![phi; s.j.len()]),
                    None if name == col::EXTREMUM_DISTANCE => Ok(s.d_ext.clone()),
                    None => Err(SolverError::InvalidArgument(format!(
                        "a solve gives no `{name}` per bin for the training-domain check"
                    ))),
                },
            )
            .collect::<Result<Vec<_>>>()?;
        Ok(Array2::from_shape_fn(
            (s.j.len(), columns.len()),
            |(k, f)| columns[f][k],
        ))
    }
}
