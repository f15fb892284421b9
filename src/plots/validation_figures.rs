//! `suspflow validate`'s figures: one SVG per unseen profile, each output of the validated
//! mappings along y, simulated (with standard-error bars where the table has them) and
//! predicted.
use anyhow::Context;
use std::path::{Path, PathBuf};
use surrogate::{profile_names, Dataset, PROFILE_COLUMN};

use crate::plots::profile_panels::{profile_panels, Panel, Series};
use crate::report::validation::Checked;

/// One figure per profile in `dir`: each output of the checked mappings along y, simulated
/// and predicted. Returns the files written.
pub fn write_figures(
    data: &Dataset,
    checked: &[Checked],
    dir: &Path,
) -> anyhow::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut outputs: Vec<&str> = checked
        .iter()
        .flat_map(|c| c.mapping.outputs.iter().copied())
        .collect();
    let columns = data.column_names();
    outputs.sort_by_key(|o| columns.iter().position(|c| c == o));
    outputs.dedup();
    let y = data.column("y")?;
    let profiles = data.text(PROFILE_COLUMN)?;
    let mut files = Vec::new();
    for (k, profile) in profile_names(data)?.iter().enumerate() {
        let rows: Vec<usize> = (0..data.n_rows())
            .filter(|&r| &profiles[r] == profile)
            .collect();
        let mut panels = Vec::new();
        for &output in &outputs {
            let values = data.column(output)?;
            let se_name = schema::columns::standard_error(output);
            let errors = if columns.contains(&se_name) {
                Some(data.column(&se_name)?)
            } else {
                None
            };
            let mut series = vec![Series {
                name: "simulated".to_owned(),
                points: rows.iter().map(|&r| (y[r], values[r])).collect(),
                errors: errors.map(|se| rows.iter().map(|&r| se[r]).collect()),
            }];
            for c in checked {
                let Some(j) = c.mapping.outputs.iter().position(|o| *o == output) else {
                    continue;
                };
                let v = &c.validation;
                series.push(Series {
                    name: format!("mapping {}", c.mapping.name),
                    points: (0..v.samples.n_rows())
                        .filter(|&i| &v.profiles[i] == profile)
                        .map(|i| (y[v.samples.data_rows[i] - 1], v.predicted[[i, j]]))
                        .collect(),
                    errors: None,
                });
            }
            panels.push(Panel {
                quantity: output.to_owned(),
                series,
            });
        }
        let path = dir.join(format!("profile_{}_{}.svg", k + 1, file_stem(profile)));
        profile_panels(&path, &figure_title(data, profile, rows[0])?, &panels)?;
        files.push(path);
    }
    Ok(files)
}

/// `u_inf = <profile>`, with L_y and phi of the profile's first row when the data has them.
fn figure_title(data: &Dataset, profile: &str, row: usize) -> anyhow::Result<String> {
    let mut title = format!("u_inf = {profile}");
    for column in ["L_y", "phi"] {
        if data.column_names().iter().any(|c| c == column) {
            title += &format!(", {column} = {}", data.text(column)?[row]);
        }
    }
    Ok(title + "; simulated vs predicted")
}

/// A file-name-safe form of a profile expression: runs of other characters become `_`.
fn file_stem(profile: &str) -> String {
    let mut stem = String::new();
    for ch in profile.chars() {
        if ch.is_ascii_alphanumeric() {
            stem.push(ch);
        } else if !stem.ends_with('_') {
            stem.push('_');
        }
    }
    stem.trim_matches('_').chars().take(60).collect()
}

#[cfg(test)]
mod tests {
    use super::file_stem;

    #[test]
    fn file_stems_keep_letters_and_digits_only() {
        assert_eq!(file_stem("0.1*sin(2*pi*y/L)^3"), "0_1_sin_2_pi_y_L_3");
        assert_eq!(file_stem("  "), "");
    }
}
