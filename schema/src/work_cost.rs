//! The one rule for work an option or a scene sets: its estimated wall time here is shown
//! before it starts, a day-long one is announced, one that cannot finish is refused. The
//! simulator's runs (`sim::input::run_cost`), the Green-Kubo and Brownian bench lengths and
//! the surrogate's learning curve all estimate their seconds and apply this rule.

/// Estimated wall time above which work is announced with a warning (one day).
pub const WARN_SECONDS: f64 = 86_400.0;

/// Estimated wall time above which work is refused (one year): none of that length
/// finishes, and a run's step counters approach the range where a strain increment per
/// step is lost in rounding.
pub const REFUSE_SECONDS: f64 = 365.0 * 86_400.0;

/// A duration for people: seconds, hours, days or years (in e-notation past 1e5 years).
pub fn describe(seconds: f64) -> String {
    const YEAR: f64 = 365.0 * 86_400.0;
    if seconds < 3600.0 {
        format!("{seconds:.0} s")
    } else if seconds < 86_400.0 {
        format!("{:.1} h", seconds / 3600.0)
    } else if seconds < YEAR {
        format!("{:.1} days", seconds / 86_400.0)
    } else if seconds / YEAR < 1e5 {
        format!("{:.1} years", seconds / YEAR)
    } else {
        format!("{:.3e} years", seconds / YEAR)
    }
}

/// Applies the rule to the `noun` (a run, a learning curve, ...) estimated at `seconds`
/// (at most) here, `what` saying what it is made of: an error, ending with `levers` (what
/// sets its length), when it exceeds [`REFUSE_SECONDS`] or has no finite length; a warning
/// when it exceeds [`WARN_SECONDS`].
pub fn check(noun: &str, seconds: f64, what: &str, levers: &str) -> Result<Option<String>, String> {
    let estimate = format!("{what}, about {} here", describe(seconds));
    if !(..=REFUSE_SECONDS).contains(&seconds) {
        return Err(format!("the {noun} cannot finish: {estimate}; {levers}"));
    }
    Ok((seconds > WARN_SECONDS).then(|| format!("long {noun}: {estimate}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_day_warns_a_year_is_refused_and_no_length_is_refused() {
        assert_eq!(check("run", 3600.0, "x", "y"), Ok(None));
        let warning = check("curve", 2.0 * WARN_SECONDS, "10 fits", "fewer")
            .unwrap()
            .unwrap();
        assert_eq!(warning, "long curve: 10 fits, about 2.0 days here");
        let refusal = check("curve", 2.0 * REFUSE_SECONDS, "10 fits", "fewer draws").unwrap_err();
        assert!(
            refusal.starts_with("the curve cannot finish: 10 fits")
                && refusal.contains("about 2.0 years here")
                && refusal.ends_with("fewer draws"),
            "{refusal}"
        );
        assert!(check("run", f64::NAN, "x", "y").is_err());
        assert!(check("run", f64::INFINITY, "x", "y").is_err());
        assert_eq!(describe(1e300), "3.171e292 years");
        assert_eq!(describe(5400.0), "1.5 h");
    }
}
