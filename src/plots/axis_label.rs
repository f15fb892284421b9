//! Axis labels with their units, so that every axis of a figure says what it measures: the
//! simulator's reduced units (docs/physics.md section 1: lengths in the small radius `a`,
//! the fluid viscosity `eta`, time in the units the scene fixes) or `dimensionless`.

/// The unit of a column or quantity named `name`, or `None` for an unknown one. A relative
/// error, and a quantity's standard error over the quantity (`Theta SE / Theta`), are
/// dimensionless whatever the quantity.
fn unit(name: &str) -> Option<&'static str> {
    let ratio_to_itself = name
        .split_once(" SE / ")
        .is_some_and(|(top, bottom)| top == bottom);
    if name.starts_with("relative") || ratio_to_itself {
        return Some("dimensionless");
    }
    Some(match name {
        "y" | "x" | "z" | "L_y" | "L_x" | "L_z" | "a" => "a",
        "u" | "u_inf" | "v" | "Delta_u" => "a / time",
        "gdot" | "shear rate" => "1 / time",
        "sigma_xy" | "P" | "sigma_yy" | "stress" | "pressure" => "eta / time",
        "f_x" => "eta / (time a)",
        "phi" | "phi_loc" | "J" | "mu" | "Theta" | "Delta_v" | "eta_r" | "Pe" | "count"
        | "rel_l2" => "dimensionless",
        _ => return None,
    })
}

/// `label` with its unit appended, e.g. `u (a / time, reduced units)`, `phi_loc
/// (dimensionless)`; a label that already states one (holds a parenthesis) as it is; an
/// unknown quantity `(reduced units)`.
pub fn with_units(label: &str) -> String {
    if label.contains('(') {
        return label.to_owned();
    }
    match unit(label.trim()) {
        Some("dimensionless") => format!("{label} (dimensionless)"),
        Some(unit) => format!("{label} ({unit}, reduced units)"),
        None => format!("{label} (reduced units)"),
    }
}

#[cfg(test)]
mod tests {
    use super::with_units;

    #[test]
    fn every_label_states_a_unit() {
        assert_eq!(with_units("u"), "u (a / time, reduced units)");
        assert_eq!(with_units("y"), "y (a, reduced units)");
        assert_eq!(with_units("phi_loc"), "phi_loc (dimensionless)");
        assert_eq!(with_units("wall time (s)"), "wall time (s)");
        assert_eq!(with_units("something"), "something (reduced units)");
        assert_eq!(
            with_units("Theta SE / Theta"),
            "Theta SE / Theta (dimensionless)"
        );
        assert_eq!(
            with_units("relative L2 validation error"),
            "relative L2 validation error (dimensionless)"
        );
        assert_eq!(with_units("u SE / Theta"), "u SE / Theta (reduced units)");
    }
}
