//! The seeds' extrapolation of a Green-Kubo running integral (paper section 3.3, Fig. 3b;
//! thesis Fig. 4.3b): `eta(s) = eta_inf (1 - exp(-s / tau))`, fitted by least squares, so
//! that a correlation still decaying at the largest lag is integrated to infinity.
use crate::error::{Result, SurrogateError};
use crate::rheology::brent;

/// A fitted single-exponential relaxation of a running integral.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Relaxation {
    /// The running integral's limit `eta_inf`.
    pub limit: f64,
    /// The relaxation time `tau` (units of the lags).
    pub time: f64,
}

/// Best `eta_inf` at relaxation time `tau` (linear least squares) and its squared error.
fn at_time(lags: &[f64], running: &[f64], tau: f64) -> (f64, f64) {
    let f: Vec<f64> = lags.iter().map(|s| 1.0 - (-s / tau).exp()).collect();
    let ff: f64 = f.iter().map(|x| x * x).sum();
    let fr: f64 = f.iter().zip(running).map(|(x, r)| x * r).sum();
    let limit = fr / ff;
    let cost = f
        .iter()
        .zip(running)
        .map(|(x, r)| (r - limit * x).powi(2))
        .sum();
    (limit, cost)
}

impl Relaxation {
    /// Fits `running` (the running integral at `lags`, ascending, from 0) with `tau`
    /// between the first lag and 100 times the last (a relaxation slower than that is
    /// not resolved by the data).
    pub fn fit(lags: &[f64], running: &[f64]) -> Result<Relaxation> {
        if lags.len() < 3 || lags.len() != running.len() || lags[1].is_nan() || lags[1] <= 0.0 {
            return Err(SurrogateError::InvalidArgument(format!(
                "a relaxation fit needs three or more ascending lags with their running \
                 integral, got {} lags and {} values",
                lags.len(),
                running.len()
            )));
        }
        let last = lags[lags.len() - 1];
        let ln_tau = brent::minimise(
            |ln_tau| at_time(lags, running, ln_tau.exp()).1,
            lags[1].ln(),
            (100.0 * last).ln(),
            "fitting the Green-Kubo relaxation",
        )?;
        let time = ln_tau.exp();
        Ok(Relaxation {
            limit: at_time(lags, running, time).0,
            time,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An exact relaxation seen only to 0.8 of its time is extrapolated to its limit.
    #[test]
    fn a_partly_relaxed_integral_is_extrapolated() {
        let lags: Vec<f64> = (0..=40).map(|k| 0.02 * k as f64).collect();
        let running: Vec<f64> = lags
            .iter()
            .map(|s| 7.0 * (1.0 - (-s / 1.0f64).exp()))
            .collect();
        let r = Relaxation::fit(&lags, &running).unwrap();
        assert!(
            (r.limit - 7.0).abs() < 1e-3 && (r.time - 1.0).abs() < 1e-3,
            "{r:?}"
        );
        assert!(running.last().unwrap() < &4.0);
        assert!(Relaxation::fit(&lags[..2], &running[..2]).is_err());
    }
}
