//! Dataset CSV files (docs/physics.md section 8): one header line, then one line per bin per
//! run (a run is one replica of a scene: its `scene_id` and `seed`).
//!
//! Lines are checked as they are read (field count, numbers where numbers belong, one
//! run's lines together) and copied byte for byte, so that assembling per-run parts,
//! or merging shards, gives the same bytes as one whole run. Scene ids sort in grid order
//! (`<grid>_<zero-padded index>`) and a scene's replicas by seed, which fixes the order of
//! the runs in every output. A run's rows, and a scene's replicas, must agree as
//! [`crate::run_rows`] says.
use crate::columns as dataset_columns;
use crate::excerpt::excerpt;
use crate::run_rows::{RunColumns, RunShape, NOT_REPLICAS};
use crate::{Result, SchemaError};
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;

/// Returns a [`SchemaError::Format`] with the formatted message.
macro_rules! bail {
    ($($arg:tt)*) => {
        return Err(SchemaError::Format(format!($($arg)*)))
    };
}

/// A [`SchemaError::Format`] with the formatted message.
macro_rules! format_error {
    ($($arg:tt)*) => {
        SchemaError::Format(format!($($arg)*))
    };
}

/// A run of a dataset: scene id and seed (`None` in a table without a `seed` column).
pub type RunKey = (String, Option<u64>);

/// The lines of one dataset file, grouped by run.
pub struct RunTable {
    pub header: String,
    /// Run -> that run's lines (without end-of-line), in file order.
    pub runs: BTreeMap<RunKey, Vec<String>>,
}

impl RunTable {
    /// Reads and checks `path`; errors name the file and the line (1 = header).
    pub fn read(path: &Path) -> Result<RunTable> {
        let bytes = std::fs::read(path).map_err(|source| SchemaError::Read {
            path: path.display().to_string(),
            source,
        })?;
        let text = String::from_utf8(bytes)
            .map_err(|e| format_error!("{}: not UTF-8 text ({e})", path.display()))?;
        Self::parse(&text).map_err(|e| SchemaError::InFile {
            path: path.display().to_string(),
            source: Box::new(e),
        })
    }

    /// Parses dataset text; see [`RunTable::read`]. A leading UTF-8 byte-order mark is
    /// dropped; scene ids must follow the safe-name rule ([`crate::scene_name`]), seeds
    /// must be non-negative integers, standard errors (`*_se`) must not be negative; the
    /// rows of a run and the runs of a scene must agree ([`crate::run_rows`]).
    pub fn parse(text: &str) -> Result<RunTable> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        if text.is_empty() {
            bail!("the file is empty (expected a header line)");
        }
        if !text.ends_with('\n') {
            bail!(
                "line {} is truncated (the file does not end with an end-of-line)",
                text.lines().count()
            );
        }
        let mut lines = text.lines();
        let header = lines.next().unwrap_or_default().to_string();
        let names = fields(&header).map_err(|m| format_error!("line 1 (header): {m}"))?;
        let id_column = names
            .iter()
            .position(|n| n == dataset_columns::SCENE_ID)
            .ok_or_else(|| {
                format_error!(
                    "line 1: no `scene_id` column in the header `{}`",
                    excerpt(&header)
                )
            })?;
        let seed_column = names.iter().position(|n| n == dataset_columns::SEED);
        let numeric: Vec<bool> = names
            .iter()
            .map(|n| !dataset_columns::TEXT.contains(&n.as_str()))
            .collect();
        let columns = RunColumns::new(&names);
        let mut runs: BTreeMap<RunKey, Vec<String>> = BTreeMap::new();
        let mut shapes: BTreeMap<RunKey, (usize, RunShape)> = BTreeMap::new();
        let mut last: Option<RunKey> = None;
        for (k, line) in lines.enumerate() {
            let number = k + 2;
            let cells = fields(line).map_err(|m| format_error!("line {number}: {m}"))?;
            if cells.len() != names.len() {
                bail!("line {number} has {} fields where the header has {} (truncated or corrupt line?)", cells.len(), names.len());
            }
            for ((cell, name), &is_number) in cells.iter().zip(&names).zip(&numeric) {
                if is_number && !cell.is_empty() && !cell.parse::<f64>().is_ok_and(f64::is_finite) {
                    bail!(
                        "line {number}, column `{name}`: `{}` is not a finite number",
                        excerpt(cell)
                    );
                }
                if dataset_columns::is_standard_error(name)
                    && cell.parse::<f64>().is_ok_and(|se| se < 0.0)
                {
                    bail!("line {number}, column `{name}`: a standard error cannot be negative ({cell})");
                }
            }
            let id = cells[id_column].clone();
            crate::scene_name::check(&id)
                .map_err(|m| format_error!("line {number}, column `scene_id`: {m}"))?;
            let seed = seed_column
                .map(|c| {
                    cells[c].parse::<u64>().map_err(|_| {
                        format_error!(
                            "line {number}, column `seed`: `{}` is not a non-negative integer",
                            excerpt(&cells[c])
                        )
                    })
                })
                .transpose()?;
            let key = (id, seed);
            if last.as_ref() != Some(&key) && runs.contains_key(&key) {
                bail!(
                    "line {number}: scene `{}`{} appears again after other runs (duplicated or interleaved rows)",
                    key.0,
                    seed_text(key.1)
                );
            }
            let y = columns.y(&cells);
            match shapes.get_mut(&key) {
                Some((_, shape)) => {
                    columns.same_run(&shape.first, &cells).map_err(|m| {
                        format_error!("line {number} (scene `{}`{}): {m}", key.0, seed_text(key.1))
                    })?;
                    shape.y.extend(y);
                }
                None => {
                    let y = Vec::from_iter(y);
                    shapes.insert(key.clone(), (number, RunShape { first: cells, y }));
                }
            }
            runs.entry(key.clone()).or_default().push(line.to_string());
            last = Some(key);
        }
        for (key, (first_line, shape)) in &shapes {
            let place = || {
                let rows = runs[key].len();
                format!(
                    "scene `{}`{}, lines {first_line}-{}",
                    key.0,
                    seed_text(key.1),
                    first_line + rows - 1
                )
            };
            columns
                .check_bins(shape)
                .map_err(|m| format_error!("{}: {m}", place()))?;
            if let Some((other, (_, first))) = shapes.range(..key).next_back() {
                if other.0 == key.0 {
                    let name = format!("seed {}", other.1.unwrap_or_default());
                    columns
                        .same_scene(first, &name, shape)
                        .map_err(|m| format_error!("{}: {m}; {NOT_REPLICAS}", place()))?;
                }
            }
        }
        Ok(RunTable { header, runs })
    }

    /// The first row and bin centres of run `key`, from its stored lines (checked on reading).
    fn shape(&self, columns: &RunColumns, key: &RunKey) -> Result<RunShape> {
        let lines = &self.runs[key];
        let first = fields(&lines[0]).map_err(SchemaError::Format)?;
        let y = lines
            .iter()
            .map(|l| Ok(columns.y(&fields(l).map_err(SchemaError::Format)?)))
            .collect::<Result<Vec<_>>>()?;
        Ok(RunShape {
            first,
            y: y.into_iter().flatten().collect(),
        })
    }

    /// Adds the runs of `other`, which must have the same header and no run in common.
    pub fn absorb(&mut self, other: RunTable, other_name: &str) -> Result<()> {
        if other.header != self.header {
            bail!(
                "{other_name}: its header differs from the first file's:\n  {}\n  {}",
                other.header,
                self.header
            );
        }
        let columns = RunColumns::new(&fields(&self.header).map_err(SchemaError::Format)?);
        for key in other.runs.keys() {
            if self.runs.contains_key(key) {
                bail!(
                    "{other_name}: scene `{}`{} is also in an earlier file (overlapping shards?)",
                    key.0,
                    seed_text(key.1)
                );
            }
            let replica = self.runs.keys().find(|(id, _)| id == &key.0);
            if let Some(replica) = replica {
                let name = format!("seed {} of an earlier file", replica.1.unwrap_or_default());
                columns
                    .same_scene(
                        &self.shape(&columns, replica)?,
                        &name,
                        &other.shape(&columns, key)?,
                    )
                    .map_err(|m| {
                        format_error!(
                            "{other_name}: scene `{}`{} {m}; {NOT_REPLICAS}",
                            key.0,
                            seed_text(key.1)
                        )
                    })?;
            }
        }
        self.runs.extend(other.runs);
        Ok(())
    }

    /// The file's text: header, then the runs in (scene id, seed) order.
    pub fn to_text(&self) -> String {
        let mut out = String::with_capacity(
            self.runs
                .values()
                .flatten()
                .map(|l| l.len() + 1)
                .sum::<usize>()
                + self.header.len()
                + 1,
        );
        out.push_str(&self.header);
        out.push('\n');
        for line in self.runs.values().flatten() {
            out.push_str(line);
            out.push('\n');
        }
        out
    }

    /// Number of data lines.
    pub fn rows(&self) -> usize {
        self.runs.values().map(Vec::len).sum()
    }

    /// The runs of each scene, scenes in table order and a scene's replicas by seed; a run is
    /// the range of its rows in [`RunTable::to_text`] (0 = the first data row).
    pub fn scenes(&self) -> Vec<Vec<Range<usize>>> {
        let mut scenes: Vec<Vec<Range<usize>>> = Vec::new();
        let mut start = 0;
        let mut last: Option<&str> = None;
        for ((id, _), lines) in &self.runs {
            let run = start..start + lines.len();
            start = run.end;
            match scenes.last_mut() {
                Some(runs) if last == Some(id.as_str()) => runs.push(run),
                _ => scenes.push(vec![run]),
            }
            last = Some(id);
        }
        scenes
    }

    /// Number of distinct scenes.
    pub fn scene_count(&self) -> usize {
        self.scenes().len()
    }

    /// Whether some scene has more than one run (replicas).
    pub fn has_replicas(&self) -> bool {
        self.scene_count() < self.runs.len()
    }
}

/// ` (seed S)` for messages, or nothing without a seed column.
fn seed_text(seed: Option<u64>) -> String {
    seed.map_or(String::new(), |s| format!(" (seed {s})"))
}

/// The fields of one CSV line (quotes removed), or what is wrong with it.
fn fields(line: &str) -> std::result::Result<Vec<String>, String> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(line.as_bytes());
    let mut record = csv::StringRecord::new();
    let read = reader
        .read_record(&mut record)
        .map_err(|e| format!("not valid CSV: {e}"))?;
    if !read {
        return Err("is empty".into());
    }
    Ok(record.iter().map(str::to_string).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "scene_id,profile,y,mu";

    /// Every text of `cases` is refused with a message holding its expected part.
    fn assert_refused(cases: &[(String, &str)]) {
        for (text, expected) in cases {
            let err = format!(
                "{:#}",
                RunTable::parse(text)
                    .err()
                    .unwrap_or_else(|| panic!("accepted {text:?}"))
            );
            assert!(err.contains(expected), "{err} should mention {expected}");
        }
    }

    #[test]
    fn merge_keeps_bytes_and_orders_scenes() {
        let mut a = RunTable::parse(&format!("{HEADER}\ng_002,\"sin(y)\",1e0,5e-1\n")).unwrap();
        let b = RunTable::parse(&format!(
            "{HEADER}\ng_000,\"sin(y)\",1e0,\ng_000,\"sin(y)\",3e0,2\n"
        ))
        .unwrap();
        a.absorb(b, "b").unwrap();
        assert_eq!(a.to_text(), format!("{HEADER}\ng_000,\"sin(y)\",1e0,\ng_000,\"sin(y)\",3e0,2\ng_002,\"sin(y)\",1e0,5e-1\n"));
        assert_eq!(a.rows(), 3);
    }

    #[test]
    fn bad_lines_are_named() {
        let cases = [
            (format!("{HEADER}\ng_0,\"s\",1,2\ng_0,\"s\",1"), "line 3"),
            (format!("{HEADER}\ng_0,\"s\",1\n"), "line 2 has 3 fields"),
            (format!("{HEADER}\ng_0,\"s\",1,x\n"), "line 2, column `mu`"),
            (
                format!("{HEADER}\ng_0,\"s\",1,NaN\n"),
                "line 2, column `mu`",
            ),
            (
                format!("{HEADER}\ng_0,\"s\",1,2\ng_1,\"s\",1,2\ng_0,\"s\",1,2\n"),
                "line 4: scene `g_0`",
            ),
            ("profile,y\nx,1\n".to_string(), "no `scene_id`"),
            (String::new(), "empty"),
            (
                format!("{HEADER}\ng_0,\"s\",1,2\n,\"s\",1,2\n"),
                "line 3, column `scene_id`: is empty",
            ),
            (
                format!("{HEADER}\n../../x,\"s\",1,2\n"),
                "line 2, column `scene_id`: `../../x` starts with '.'",
            ),
            (
                "scene_id,y,mu_se\ng_0,1,-0.5\n".to_string(),
                "line 2, column `mu_se`: a standard error cannot be negative",
            ),
            (
                format!("{HEADER}\ng_0,\"s\",1,{}\n", "7".repeat(500_000) + "x"),
                "... (500001 bytes)` is not a finite number",
            ),
        ];
        assert_refused(&cases);
    }

    #[test]
    fn replicas_are_runs_ordered_by_seed() {
        const SEEDED: &str = "scene_id,seed,y";
        let mut a = RunTable::parse(&format!("{SEEDED}\ng_0,10,1\ng_0,10,3\n")).unwrap();
        let b = RunTable::parse(&format!("{SEEDED}\ng_1,1,1\ng_0,2,1\ng_0,2,3\n")).unwrap();
        a.absorb(b, "b").unwrap();
        assert_eq!(
            a.to_text(),
            format!("{SEEDED}\ng_0,2,1\ng_0,2,3\ng_0,10,1\ng_0,10,3\ng_1,1,1\n")
        );
        assert_eq!((a.runs.len(), a.scene_count()), (3, 2));
        let single: Vec<std::ops::Range<usize>> = std::iter::once(4..5).collect();
        assert_eq!(a.scenes(), [vec![0..2, 2..4], single]);
        assert!(a.has_replicas());
        let again = RunTable::parse(&format!("{SEEDED}\ng_0,2,5\n")).unwrap();
        let message = format!("{:#}", a.absorb(again, "c").unwrap_err());
        assert!(
            message.contains("scene `g_0` (seed 2) is also in an earlier file"),
            "{message}"
        );
        for (text, expected) in [
            (
                format!("{SEEDED}\ng_0,1.5,1\n"),
                "line 2, column `seed`: `1.5` is not a non-negative integer",
            ),
            (
                format!("{SEEDED}\ng_0,1,1\ng_0,2,1\ng_0,1,3\n"),
                "line 4: scene `g_0` (seed 1) appears again",
            ),
        ] {
            let message = format!("{:#}", RunTable::parse(&text).err().unwrap());
            assert!(message.contains(expected), "{message}");
        }
    }

    /// Issue 31, class 9: a run's rows share its scene, its bins tile the box once each, and
    /// a scene's replicas share its scene columns and bins (independent of how the ensemble
    /// is built: these are refused before it).
    #[test]
    fn runs_that_disagree_are_refused() {
        const RUN: &str = "scene_id,L_y,phi,seed,y";
        let run = |seed: u32, phi: &str, ys: &[&str]| -> String {
            ys.iter()
                .map(|y| format!("g_0,4,{phi},{seed},{y}\n"))
                .collect()
        };
        let good = format!(
            "{RUN}\n{}{}",
            run(1, "0.5", &["1", "3"]),
            run(2, "5e-1", &["1e0", "3"])
        );
        assert_eq!(RunTable::parse(&good).unwrap().runs.len(), 2);
        let cases = [
            (
                format!("{RUN}\n{}", run(1, "0.5", &["1", "1"])),
                "scene `g_0` (seed 1), lines 2-3: bin 2 (y = 1) does not come after bin 1 (y = 1): a bin is duplicated",
            ),
            (
                format!("{RUN}\n{}", run(1, "0.5", &["1"])),
                "its 1 bins do not tile L_y = 4: bin 1 is at y = 1, not at 2",
            ),
            (
                format!("{RUN}\n{}", run(1, "0.5", &["0.5", "1.5", "3.5"])),
                "its 3 bins do not tile L_y = 4: bin 1 is at y = 0.5, not at 0.666",
            ),
            (
                format!("{RUN}\ng_0,4,0.5,1,1\ng_0,4,0.44,1,3\n"),
                "line 3 (scene `g_0` (seed 1)): column `phi` is `0.44` where the run's first row has `0.5`",
            ),
            (
                format!("{RUN}\n{}{}", run(1, "0.5", &["1", "3"]), run(2, "0.44", &["1", "3"])),
                "scene `g_0` (seed 2), lines 4-5: has phi = `0.44` where seed 1 has `0.5`; replicas of a scene differ only in their seed",
            ),
            (
                format!("{RUN}\n{}{}", run(1, "0.5", &["1", "3"]), run(2, "0.5", &["2"])),
                "has other bins (1 from y = 2) than seed 1 (2 from y = 1)",
            ),
        ];
        assert_refused(&cases);
        // Across files: a second grid's run under the same scene name and another seed.
        let mut a = RunTable::parse(&format!("{RUN}\n{}", run(1, "0.45", &["1", "3"]))).unwrap();
        let b = RunTable::parse(&format!("{RUN}\n{}", run(2, "0.44", &["1", "3"]))).unwrap();
        let err = format!("{:#}", a.absorb(b, "b.csv").unwrap_err());
        assert!(
            err.contains("b.csv: scene `g_0` (seed 2) has phi = `0.44` where seed 1 of an earlier file has `0.45`"),
            "{err}"
        );
    }

    #[test]
    fn byte_order_mark_is_dropped() {
        let plain = RunTable::parse(&format!("{HEADER}\ng_0,\"s\",1,2\n")).unwrap();
        let mut marked = RunTable::parse(&format!("\u{feff}{HEADER}\ng_1,\"s\",1,2\n")).unwrap();
        assert_eq!(marked.header, HEADER);
        marked.absorb(plain, "plain").unwrap();
        assert_eq!(marked.rows(), 2);
    }

    #[test]
    fn overlapping_or_mismatched_files_are_refused() {
        let mut a = RunTable::parse(&format!("{HEADER}\ng_0,\"s\",1,2\n")).unwrap();
        let same = RunTable::parse(&format!("{HEADER}\ng_0,\"s\",1,2\n")).unwrap();
        assert!(
            format!("{:#}", a.absorb(same, "b").unwrap_err()).contains("also in an earlier file")
        );
        let other = RunTable::parse("scene_id,y\ng_1,1\n").unwrap();
        assert!(format!("{:#}", a.absorb(other, "c").unwrap_err()).contains("header differs"));
    }
}
