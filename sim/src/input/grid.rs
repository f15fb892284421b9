//! Grid files (TOML): a set of scenes for `suspflow generate`, written as fixed scene
//! settings plus the fields that vary.
//!
//! ```toml
//! name = "train"                 # prefix of the scene ids
//! replicas = 3                   # optional: runs per scene, seeds derived (see below)
//! [scene]                        # any scene-file field, fixed for every scene
//! box = { l_x = 17.0, l_z = 17.0 }
//! fluid = { profile = "0.1*sin(2*pi*y/L)" }
//! [vary]                         # Cartesian product over these lists
//! "particles.phi" = [0.50, 0.52]
//! "box.l_y" = [50.0, 100.0]
//! [[cases]]                      # optional: fields that change together, one table per case
//! "fluid.profile" = "0.1*sin(2*pi*y/L)^3"
//! "box.l_y" = 100.0
//! ```
//!
//! Scenes are numbered cases first, then the `vary` keys in alphabetical order with the
//! last key varying fastest; scene `k` is named `<name>_<k>` with `k` zero-padded, so that
//! sorting ids sorts scenes in grid order.
//!
//! A grid may start from another's scenes: a top-level `base = "other.toml"` (a path
//! relative to this file) takes the other grid's `[scene]` (itself with its own base, if
//! any) and sets this grid's `[scene]` entries on it, section by section (`run = { dt = 1.0 }`
//! sets `run.dt` and keeps the base's other `run` entries); the base's name, `[vary]` and
//! cases are not taken.
//!
//! Replicas: a scene whose `seed` is a list (`seed = [1, 2, 3]`, in `[scene]` or a case), or
//! every scene of a grid with a top-level `replicas = R`, runs once per seed (see
//! [`crate::input::replica_seeds`]). Each replica is one [`GridRun`]: the replicas of a scene
//! share its id and differ in `seed`.
use crate::error::SimError;
use crate::input::replica_seeds::replica_seeds;
use crate::input::scene::{Scene, SceneFile};
use crate::input::scene_limits::show;
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use toml::{Table, Value};

/// A grid file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct GridFile {
    name: String,
    #[serde(default)]
    scene: Table,
    #[serde(default)]
    vary: BTreeMap<String, Value>,
    #[serde(default)]
    cases: Vec<BTreeMap<String, Value>>,
    /// Replicas of every scene, seeds derived from the scene's seed.
    replicas: Option<i64>,
    /// A grid file (relative to this one) whose `[scene]` this grid's is set on.
    base: Option<String>,
}

/// Longest chain of grids on bases: a longer one is a cycle, or nearly.
const BASE_DEPTH_MAX: usize = 8;

/// Sets every entry of `over` on `table`: a section present in both is set entry by entry,
/// anything else replaced.
fn set_on(table: &mut Table, over: &Table) {
    for (key, value) in over {
        match (table.get_mut(key), value) {
            (Some(Value::Table(below)), Value::Table(above)) => set_on(below, above),
            _ => {
                table.insert(key.clone(), value.clone());
            }
        }
    }
}

/// The `[scene]` of `file`, set on its base's (read relative to `dir`, the folder of the
/// file, if known), `depth` bases down from the grid being read.
fn scene_on_base(file: &GridFile, dir: Option<&Path>, depth: usize) -> Result<Table, SimError> {
    let Some(base) = &file.base else {
        return Ok(file.scene.clone());
    };
    let dir = dir.ok_or_else(|| {
        grid_error(format!(
            "`base = \"{base}\"` names a file relative to the grid's: read the grid from its file"
        ))
    })?;
    if depth >= BASE_DEPTH_MAX {
        return Err(grid_error(format!(
            "more than {BASE_DEPTH_MAX} grids on bases, down to {base}: a cycle?"
        )));
    }
    let path = dir.join(base);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| grid_error(format!("base {}: {e}", path.display())))?;
    let below: GridFile =
        toml::from_str(&text).map_err(|e| grid_error(format!("base {}: {e}", path.display())))?;
    let mut scene = scene_on_base(&below, path.parent(), depth + 1)?;
    set_on(&mut scene, &file.scene);
    Ok(scene)
}

/// One run of a grid: one replica of one scene, validated.
#[derive(Clone, Debug)]
pub struct GridRun {
    /// Position of the scene in the grid (0-based).
    pub index: usize,
    /// `<grid name>_<index>`, also the scene's `name`; the same for every replica.
    pub id: String,
    /// The scene with this replica's seed (`scene.file.seed`).
    pub scene: Scene,
}

impl GridRun {
    /// The replica's seed.
    pub fn seed(&self) -> u64 {
        self.scene.file.seed
    }

    /// `<id>_seed<seed>`: names the replica's work folder and its log lines.
    pub fn label(&self) -> String {
        format!("{}_seed{}", self.id, self.seed())
    }
}

/// An expanded grid.
#[derive(Clone, Debug)]
pub struct Grid {
    pub name: String,
    /// Every replica of every scene, scenes in grid order, each scene's replicas in the
    /// order of its seeds.
    pub runs: Vec<GridRun>,
}

/// A scene as the values it holds, without its name and the spelling of its values: the
/// parsed file (where `12` and `12.0` are one number and dotted and inline tables one
/// table) with the profile's whitespace removed.
fn spelling_free(file: &SceneFile) -> String {
    let mut file = file.clone();
    file.name.clear();
    file.fluid.profile.retain(|c| !c.is_whitespace());
    serde_json::to_string(&file).unwrap_or_default()
}

fn grid_error(message: impl Into<String>) -> SimError {
    SimError::Grid(message.into())
}

/// Sets the dotted scene field `path` (e.g. `particles.phi`) in `table`.
fn set_field(table: &mut Table, path: &str, value: Value) -> Result<(), SimError> {
    let mut keys = path.split('.').peekable();
    let mut here = table;
    while let Some(key) = keys.next() {
        if key.is_empty() {
            return Err(grid_error(format!("`{path}` is not a scene field path")));
        }
        if keys.peek().is_none() {
            here.insert(key.to_string(), value);
            return Ok(());
        }
        let next = here
            .entry(key.to_string())
            .or_insert_with(|| Value::Table(Table::new()));
        here = next
            .as_table_mut()
            .ok_or_else(|| grid_error(format!("`{path}`: `{key}` is a value, not a section")))?;
    }
    Ok(())
}

/// Most runs a grid may expand to: each is validated before the first starts, and each
/// gets a work folder; 1e5 runs of the smallest scenes are already weeks here.
pub const GRID_RUNS_MAX: usize = 100_000;

/// Scenes of `cases` cases times the product of the `vary` lists, refused (before any is
/// built) when they, times the grid's `replicas`, exceed [`GRID_RUNS_MAX`].
fn grid_size(
    cases: usize,
    lists: &[(&str, &[Value])],
    replicas: Option<i64>,
) -> Result<usize, SimError> {
    let replicas = replicas.unwrap_or(1).max(1);
    let scenes = lists
        .iter()
        .try_fold(cases, |n, (_, values)| n.checked_mul(values.len()));
    let runs = scenes.and_then(|n| n.checked_mul(usize::try_from(replicas).ok()?));
    match (scenes, runs) {
        (Some(scenes), Some(runs)) if runs <= GRID_RUNS_MAX => Ok(scenes),
        _ => {
            let product: f64 = lists.iter().map(|(_, v)| v.len() as f64).product();
            let runs = cases as f64 * product * replicas as f64;
            Err(grid_error(format!(
                "expands to {} runs ({cases} case(s) x {} [vary] combinations x {replicas} \
                 replica(s)), more than {GRID_RUNS_MAX}: split it into smaller grids",
                show(runs),
                show(product)
            )))
        }
    }
}

impl Grid {
    /// Reads and expands a grid file; every scene is validated as a scene file would be.
    pub fn from_path(path: &Path, strict: bool) -> Result<Grid, SimError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| grid_error(format!("{}: {e}", path.display())))?;
        Self::expand(&text, path.parent(), strict).map_err(|e| match e {
            SimError::Grid(m) => grid_error(format!("{}: {m}", path.display())),
            other => other,
        })
    }

    /// Expands grid text (see the module documentation); a grid with a `base` is refused
    /// (its base is found from its file: [`Self::from_path`]).
    pub fn from_toml(text: &str, strict: bool) -> Result<Grid, SimError> {
        Self::expand(text, None, strict)
    }

    /// Expands grid text read from a file in the folder `dir` (its `base` relative to it).
    fn expand(text: &str, dir: Option<&Path>, strict: bool) -> Result<Grid, SimError> {
        let file: GridFile = toml::from_str(text).map_err(|e| grid_error(e.to_string()))?;
        let scene = scene_on_base(&file, dir, 0)?;
        if file.name.is_empty()
            || !file
                .name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(grid_error(format!(
                "name `{}` must be non-empty letters, digits, - or _ (it names files)",
                file.name
            )));
        }
        let mut lists = Vec::new();
        for (key, value) in &file.vary {
            match value {
                Value::Array(values) if !values.is_empty() => {
                    if let Some(twice) = values
                        .iter()
                        .enumerate()
                        .find_map(|(k, v)| values[..k].contains(v).then_some(v))
                    {
                        return Err(grid_error(format!(
                            "vary.\"{key}\" lists {twice} twice: the grid would run the same scene twice"
                        )));
                    }
                    lists.push((key.as_str(), values.as_slice()))
                }
                _ => {
                    return Err(grid_error(format!(
                        "vary.\"{key}\" must be a non-empty list of values"
                    )))
                }
            }
            if file.cases.iter().any(|c| c.contains_key(key)) {
                return Err(grid_error(format!(
                    "`{key}` is both in [vary] and in a [[cases]] table"
                )));
            }
        }
        if file.vary.contains_key("name") {
            return Err(grid_error(
                "[vary] lists `name`; scene names are `<grid name>_<index>`, and scenes that \
                 differ only in their name are one scene",
            ));
        }
        for (k, case) in file.cases.iter().enumerate() {
            if case.contains_key("name") {
                return Err(grid_error(format!(
                    "cases[{k}] sets `name`; scene names are `<grid name>_<index>`"
                )));
            }
            if let Some(first) = file.cases[..k].iter().position(|c| c == case) {
                return Err(grid_error(format!(
                    "cases[{first}] and cases[{k}] are the same case: the grid would run the same scene twice"
                )));
            }
        }
        let no_case = BTreeMap::new();
        let cases: Vec<&BTreeMap<String, Value>> = if file.cases.is_empty() {
            vec![&no_case]
        } else {
            file.cases.iter().collect()
        };
        let total = grid_size(cases.len(), &lists, file.replicas)?;
        // Bounded by `total` (checked above without overflow), so the product cannot overflow.
        let per_case: usize = lists.iter().map(|(_, v)| v.len()).product();
        let width = total.saturating_sub(1).to_string().len().max(3);
        let mut runs = Vec::with_capacity(total);
        let mut seen: HashMap<String, String> = HashMap::new();
        for (c, case) in cases.iter().enumerate() {
            for combo in 0..per_case {
                let index = c * per_case + combo;
                let id = format!("{}_{index:0width$}", file.name);
                let mut table = scene.clone();
                for (key, value) in case.iter() {
                    set_field(&mut table, key, value.clone())?;
                }
                let mut rest = combo;
                for (key, values) in lists.iter().rev() {
                    set_field(&mut table, key, values[rest % values.len()].clone())?;
                    rest /= values.len();
                }
                table.insert("name".into(), Value::String(id.clone()));
                if table.contains_key("replicas") {
                    return Err(grid_error(format!(
                        "scene {id}: `replicas` is a key of the grid, not of a scene: \
                         write it at the top of the file, before [scene]"
                    )));
                }
                let seeds = replica_seeds(table.get("seed"), file.replicas)
                    .map_err(|m| grid_error(format!("scene {id}: {m}")))?;
                for seed in seeds {
                    table.insert("seed".into(), Value::Integer(seed as i64));
                    let scene_file: SceneFile = Value::Table(table.clone())
                        .try_into()
                        .map_err(|e| grid_error(format!("scene {id}: {e}")))?;
                    if let Some(first) = seen.insert(spelling_free(&scene_file), id.clone()) {
                        return Err(grid_error(format!(
                            "scenes {first} and {id} are the same scene (seed {seed}) with \
                             values spelled two ways (12 and 12.0, spaces in the profile, \
                             ...): the grid would run it twice, and its copies would leak \
                             across cross-validation folds"
                        )));
                    }
                    let scene = Scene::from_file(scene_file, strict)
                        .map_err(|e| grid_error(format!("scene {id}: {e}")))?;
                    runs.push(GridRun {
                        index,
                        id: id.clone(),
                        scene,
                    });
                }
            }
        }
        Ok(Grid {
            name: file.name,
            runs,
        })
    }

    /// Number of scenes (each with one or more runs).
    pub fn scene_count(&self) -> usize {
        self.runs.last().map_or(0, |r| r.index + 1)
    }

    /// The runs of shard `i` of `n` (0 <= i < n): every n-th run from the i-th, so that the
    /// shards are disjoint, cover the grid, and each gets a share of every setting.
    pub fn shard(&self, i: usize, n: usize) -> Result<Vec<&GridRun>, SimError> {
        if n == 0 || i >= n {
            return Err(grid_error(format!("shard {i}/{n}: need 0 <= i < n")));
        }
        Ok(self
            .runs
            .iter()
            .enumerate()
            .filter(|(k, _)| k % n == i)
            .map(|(_, r)| r)
            .collect())
    }
}
