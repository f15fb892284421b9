//! Numbers that JSON cannot hold: serde_json writes NaN and the infinities as `null`; these
//! read such a `null` back as the value it stood for. The floor of the crate (no stage
//! imports above it), used by the summaries and time steps written to JSON.
use serde::{Deserialize, Deserializer};

/// Reads a number that JSON holds as `null` when it was not finite (serde_json writes NaN
/// and the infinities so) as NaN.
pub fn null_as_nan<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Reads a limit that JSON holds as `null` when it was infinite (no such limit) as infinity.
pub fn null_as_infinity<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
}
