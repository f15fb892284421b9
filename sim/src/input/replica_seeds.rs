//! The seeds of a grid scene's replicas: independent realisations of one scene that differ
//! only in the RNG seed of the initial packing.
//!
//! A scene gets its replicas either from a list, `seed = [1, 2, 3]` (in `[scene]` or a
//! `[[cases]]` table), or from the grid's `replicas = R` count, which derives `R` seeds from
//! the scene's single `seed` (default 1): replica 0 keeps that seed, so `replicas = 1` is the
//! plain scene, and replica `r > 0` gets [`derived_seed`]. Derived seeds are hashed rather
//! than `seed + r`, so that scenes which vary `seed` in `[vary]` do not share replicas.

/// Default seed of a scene file that sets none (the scene file's default).
const DEFAULT_SEED: u64 = 1;

/// Seed of replica `replica` (> 0) of a scene whose own seed is `base`: the upper 32 bits of
/// SplitMix64 (Steele, Lea and Flood 2014) applied to `base + replica * golden ratio`, so
/// that it fits a TOML integer and reads short in tables.
pub fn derived_seed(base: u64, replica: u64) -> u64 {
    let mut z = base.wrapping_add(replica.wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (z ^ (z >> 31)) >> 32
}

/// The replica seeds of one scene, in the order given: `seed` is the scene's `seed` value as
/// written (absent, an integer or a list), `replicas` the grid's count. Errors say what is
/// wrong with the list or the count; the caller names the scene.
pub fn replica_seeds(
    seed: Option<&toml::Value>,
    replicas: Option<i64>,
) -> Result<Vec<u64>, String> {
    let as_seed = |v: &toml::Value| match v.as_integer() {
        Some(s) if s >= 0 => Ok(s as u64),
        _ => Err(format!("seed {v} is not a non-negative integer")),
    };
    match (seed, replicas) {
        (Some(toml::Value::Array(list)), Some(_)) => Err(format!(
            "`seed` lists {} seeds and the grid sets `replicas`: give one or the other",
            list.len()
        )),
        (Some(toml::Value::Array(list)), None) => {
            if list.is_empty() {
                return Err("`seed = []` lists no seed: give at least one".into());
            }
            let seeds = list.iter().map(as_seed).collect::<Result<Vec<u64>, _>>()?;
            match seeds
                .iter()
                .enumerate()
                .find(|&(k, s)| seeds[..k].contains(s))
            {
                Some((_, twice)) => Err(format!(
                    "`seed` lists {twice} twice: two replicas would be the same run"
                )),
                None => Ok(seeds),
            }
        }
        (seed, replicas) => {
            let base = seed.map(as_seed).transpose()?.unwrap_or(DEFAULT_SEED);
            match replicas {
                None => Ok(vec![base]),
                Some(r) if r < 1 => Err(format!(
                    "`replicas = {r}`: a scene needs at least one replica"
                )),
                Some(r) => Ok((0..r as u64)
                    .map(|k| if k == 0 { base } else { derived_seed(base, k) })
                    .collect()),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn derived_seeds_are_distinct_and_fit_a_toml_integer() {
        let seeds: Vec<u64> = (1..1000).map(|r| derived_seed(1, r)).collect();
        let mut sorted = seeds.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), seeds.len());
        assert!(seeds.iter().all(|&s| s <= u32::MAX as u64 && s != 1));
        // Neighbouring base seeds give unrelated replicas.
        assert_ne!(derived_seed(1, 1), derived_seed(2, 1));
        assert_ne!(derived_seed(2, 1), derived_seed(1, 2));
    }
}
