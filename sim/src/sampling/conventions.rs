//! The observable conventions (docs/physics.md section 6), the `[observables]` table of a
//! scene file: which stress, which velocity fluctuation for Theta (6.1), which u_inf for
//! Delta_v (6.2) and which derivative for gdot. Each default is the thesis' definition;
//! every option is computed from the same snapshot sums, so one run gives them all.
use serde::{Deserialize, Serialize};

/// Which terms the reported stress `sigma` holds (positive in compression).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum StressConvention {
    /// Pair stresslets only, contact plus lubrication (as LAMMPS' per-atom stress reports
    /// them in the thesis' runs).
    #[default]
    #[serde(rename = "pairs")]
    Pairs,
    /// Pair stresslets plus the one-body drag stresslets `(20/3) pi eta a^3 E` of the
    /// particles centred in the bin.
    #[serde(rename = "pairs+drag")]
    PairsDrag,
    /// Pairs, drag stresslets and the solvent stress `eta gdot` (xy only).
    #[serde(rename = "pairs+drag+solvent")]
    PairsDragSolvent,
}

/// The velocity fluctuation `du` of Theta (6.1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ThetaConvention {
    /// Per snapshot `du_i = |v_x,i - u*_i|`, `u*_i` the mean x-velocity of the particles
    /// centred within +-0.1 a of `y_i` (thesis section 6.3), averaged over the bin's
    /// particles and snapshots.
    #[default]
    LocalWindow,
    /// r.m.s. of `v_x,i` about the time-averaged bin means interpolated linearly between
    /// bin centres to `y_i`.
    InterpolatedRms,
}

/// The streaming velocity `u_inf` of Delta_v (6.2).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DeltaVConvention {
    /// `u_inf(y_i)` averaged over the bin's particles and snapshots, as `u` is.
    #[default]
    ParticleAverage,
    /// `u_inf` at the bin centre.
    BinCentre,
}

/// The derivative `gdot = du/dy` of the time-averaged binned velocity.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum GdotConvention {
    /// Periodic spectral derivative: for a band-limited profile, exactly the bin average of
    /// `du/dy`.
    #[default]
    Spectral,
    /// Centred difference `(u_{k+1} - u_{k-1}) / 2w`, low by `1 - sinc(2 pi w / lambda)` on
    /// a wave of length lambda.
    Centred,
}

/// The `[observables]` table of a scene file; every field defaults to the thesis' definition.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Conventions {
    #[serde(default)]
    pub stress: StressConvention,
    #[serde(default)]
    pub theta: ThetaConvention,
    #[serde(default)]
    pub delta_v: DeltaVConvention,
    #[serde(default)]
    pub gdot: GdotConvention,
}

impl Conventions {
    /// Every convention that differs from the default in one option, labelled with that
    /// option as written in a scene file (`stress = "pairs+drag"`, ...).
    pub fn alternatives() -> Vec<(String, Conventions)> {
        let d = Conventions::default();
        let mut out = Vec::new();
        for stress in [
            StressConvention::PairsDrag,
            StressConvention::PairsDragSolvent,
        ] {
            out.push((label("stress", stress), Conventions { stress, ..d }));
        }
        let theta = ThetaConvention::InterpolatedRms;
        out.push((label("theta", theta), Conventions { theta, ..d }));
        let delta_v = DeltaVConvention::BinCentre;
        out.push((label("delta_v", delta_v), Conventions { delta_v, ..d }));
        let gdot = GdotConvention::Centred;
        out.push((label("gdot", gdot), Conventions { gdot, ..d }));
        out
    }
}

/// `key = "value"` with the value as a scene file spells it.
fn label(key: &str, value: impl Serialize) -> String {
    let value = serde_json::to_value(value).expect("a unit variant serialises");
    format!("{key} = {value}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_thesis_definitions_and_unknown_values_are_refused() {
        let c: Conventions = toml::from_str("").unwrap();
        assert_eq!(c.stress, StressConvention::Pairs);
        assert_eq!(c.theta, ThetaConvention::LocalWindow);
        assert_eq!(c.delta_v, DeltaVConvention::ParticleAverage);
        assert_eq!(c.gdot, GdotConvention::Spectral);
        let c: Conventions =
            toml::from_str("stress = \"pairs+drag+solvent\"\ngdot = \"centred\"").unwrap();
        assert_eq!(c.stress, StressConvention::PairsDragSolvent);
        assert_eq!(c.gdot, GdotConvention::Centred);
        let e = toml::from_str::<Conventions>("theta = \"rms\"")
            .unwrap_err()
            .to_string();
        assert!(e.contains("rms") && e.contains("local-window"), "{e}");
        assert!(toml::from_str::<Conventions>("stres = \"pairs\"").is_err());
        let labels: Vec<String> = Conventions::alternatives()
            .into_iter()
            .map(|(l, _)| l)
            .collect();
        assert!(
            labels.contains(&"stress = \"pairs+drag\"".to_string()),
            "{labels:?}"
        );
        assert!(
            labels.contains(&"theta = \"interpolated-rms\"".to_string()),
            "{labels:?}"
        );
    }
}
