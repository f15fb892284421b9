//! What the rows of one run of a dataset must share, and what the runs of one scene must
//! share (docs/physics.md section 8): `merge` and `generate` refuse a table that breaks it
//! rather than average rows of different scenes into one ensemble row.
//!
//! - A run (one `scene_id` and `seed`) has one value of each per-run column ([`PER_RUN`]:
//!   the scene's `profile`, `L_y`, `phi`, the run's seed, steady strain, residual, version)
//!   on all its rows.
//! - Its bins are distinct, in order, and tile the box: n rows of a box `L_y` have their
//!   centres at `y_k = (k + 1/2) L_y / n` (a missing or duplicated bin breaks this).
//! - The replicas of a scene (runs that differ only in `seed`) agree on the scene columns
//!   ([`SCENE`]) and on the bins. Two grids that give one scene name to different scenes
//!   are caught here when the scenes differ in these columns; what the dataset does not
//!   record (stiffness, radii, ...) cannot be compared.
use crate::columns as col;
use crate::excerpt::excerpt;

/// Columns that hold one value for a whole run (those of a per-run dataset and of an
/// ensemble table).
const PER_RUN: [&str; 10] = [
    col::PROFILE,
    col::L_Y,
    col::PHI,
    col::SEED,
    col::STEADY_STRAIN,
    col::MOMENTUM_RESIDUAL,
    col::CODE_VERSION,
    col::REPLICAS,
    col::SEEDS,
    col::SE_FROM,
];

/// Columns that define the scene: its replicas agree on them.
const SCENE: [&str; 3] = [col::PROFILE, col::L_Y, col::PHI];

/// Relative tolerance (of `L_y`) on a bin centre: the centres are written with 17 digits.
const BIN_CENTRE_TOLERANCE: f64 = 1e-9;

/// One run as the checks see it: its first row's cells and its bin centres in row order.
pub struct RunShape {
    pub first: Vec<String>,
    pub y: Vec<f64>,
}

/// Where the checked columns are in a table's header.
pub struct RunColumns {
    per_run: Vec<(usize, &'static str)>,
    scene: Vec<(usize, &'static str)>,
    y: Option<usize>,
    l_y: Option<usize>,
}

impl RunColumns {
    /// The checked columns among `names` (a table may lack some).
    pub fn new(names: &[String]) -> Self {
        let find = |wanted: &[&'static str]| -> Vec<(usize, &'static str)> {
            wanted
                .iter()
                .filter_map(|&w| names.iter().position(|n| n == w).map(|i| (i, w)))
                .collect()
        };
        let at = |name: &str| names.iter().position(|n| n == name);
        RunColumns {
            per_run: find(&PER_RUN),
            scene: find(&SCENE),
            y: at(col::Y),
            l_y: at(col::L_Y),
        }
    }

    /// The bin centre of a row, when the table has a `y` column (checked as a number).
    pub fn y(&self, cells: &[String]) -> Option<f64> {
        self.y.and_then(|c| cells[c].parse().ok())
    }

    /// `Err(what differs)` when row `cells` has another value than the run's first row
    /// `first` in a per-run column.
    pub fn same_run(&self, first: &[String], cells: &[String]) -> Result<(), String> {
        match self
            .per_run
            .iter()
            .find(|&&(c, _)| !same_cell(&first[c], &cells[c]))
        {
            None => Ok(()),
            Some(&(c, name)) => Err(format!(
                "column `{name}` is `{}` where the run's first row has `{}`: the rows of a \
                 run share its scene and run columns",
                excerpt(&cells[c]),
                excerpt(&first[c])
            )),
        }
    }

    /// `Err(what is wrong)` unless the run's bins are distinct, increasing and, with an
    /// `L_y` column, the centres `(k + 1/2) L_y / n` of `n` equal bins.
    pub fn check_bins(&self, run: &RunShape) -> Result<(), String> {
        if let Some(k) = (1..run.y.len()).find(|&k| run.y[k] <= run.y[k - 1]) {
            return Err(format!(
                "bin {} (y = {}) does not come after bin {} (y = {}): a bin is duplicated or \
                 the rows are out of order",
                k + 1,
                run.y[k],
                k,
                run.y[k - 1]
            ));
        }
        let Some(l_y) = self.l_y.and_then(|c| run.first[c].parse::<f64>().ok()) else {
            return Ok(());
        };
        let n = run.y.len();
        let width = l_y / n as f64;
        match (0..n)
            .find(|&k| ((k as f64 + 0.5) * width - run.y[k]).abs() > BIN_CENTRE_TOLERANCE * l_y)
        {
            None => Ok(()),
            Some(k) => Err(format!(
                "its {n} bins do not tile L_y = {l_y}: bin {} is at y = {}, not at {} = \
                 ({} + 1/2) L_y / {n} (a bin is missing, or rows of another box)",
                k + 1,
                run.y[k],
                (k as f64 + 0.5) * width,
                k
            )),
        }
    }

    /// `Err(what differs)` when run `b` is not a replica of the scene of run `a` (named
    /// `a_name` in the message): another value in a scene column, or other bins.
    pub fn same_scene(&self, a: &RunShape, a_name: &str, b: &RunShape) -> Result<(), String> {
        if let Some(&(c, name)) = self
            .scene
            .iter()
            .find(|&&(c, _)| !same_cell(&a.first[c], &b.first[c]))
        {
            return Err(format!(
                "has {name} = `{}` where {a_name} has `{}`",
                excerpt(&b.first[c]),
                excerpt(&a.first[c])
            ));
        }
        if a.y != b.y {
            return Err(format!(
                "has other bins ({} from y = {}) than {a_name} ({} from y = {})",
                b.y.len(),
                b.y.first().copied().unwrap_or(f64::NAN),
                a.y.len(),
                a.y.first().copied().unwrap_or(f64::NAN)
            ));
        }
        Ok(())
    }
}

/// The end of a message on runs of one scene name that are not replicas of one scene.
pub const NOT_REPLICAS: &str =
    "replicas of a scene differ only in their seed (runs of two grids under one scene name?)";

/// Two cells hold the same value: the same text, or the same number (`12` and `1.2e1`).
fn same_cell(a: &str, b: &str) -> bool {
    a == b
        || matches!(
            (a.parse::<f64>(), b.parse::<f64>()),
            (Ok(x), Ok(y)) if x == y
        )
}
