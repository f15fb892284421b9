//! Fingerprint of a table: identifies the exact bytes a model was trained on or a
//! cross-validation was run over. Written in metadata as 16 hexadecimal digits.

use std::fmt;

/// 64-bit FNV-1a hash of a file's bytes (not cryptographic: it only tells whether the data
/// changed), written and read as 16 lower-case hexadecimal digits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Fingerprint(pub u64);

impl Fingerprint {
    /// The FNV-1a hash of `bytes`. Written out here because it takes four lines and needs no
    /// dependency.
    pub fn of(bytes: &[u8]) -> Fingerprint {
        const OFFSET_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
        const PRIME: u64 = 0x0000_0100_0000_01b3;
        Fingerprint(bytes.iter().fold(OFFSET_BASIS, |hash, &byte| {
            (hash ^ u64::from(byte)).wrapping_mul(PRIME)
        }))
    }
}

impl fmt::Display for Fingerprint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:016x}", self.0)
    }
}

impl serde::Serialize for Fingerprint {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for Fingerprint {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = String::deserialize(deserializer)?;
        if text.len() != 16 {
            return Err(serde::de::Error::custom(format!(
                "fingerprint `{}` is not 16 hexadecimal digits",
                crate::excerpt::excerpt(&text)
            )));
        }
        u64::from_str_radix(&text, 16)
            .map(Fingerprint)
            .map_err(|_| {
                serde::de::Error::custom(format!(
                    "fingerprint `{text}` is not 16 hexadecimal digits"
                ))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::Fingerprint;

    #[test]
    fn matches_published_test_vectors() {
        assert_eq!(Fingerprint::of(b"").0, 0xcbf2_9ce4_8422_2325);
        assert_eq!(Fingerprint::of(b"a").0, 0xaf63_dc4c_8601_ec8c);
        assert_eq!(Fingerprint::of(b"foobar").0, 0x8594_4171_f739_67e8);
    }

    #[test]
    fn is_written_as_sixteen_hex_digits_and_read_back() {
        let f = Fingerprint(0xaf);
        let json = serde_json::to_string(&f).unwrap();
        assert_eq!(json, "\"00000000000000af\"");
        assert_eq!(serde_json::from_str::<Fingerprint>(&json).unwrap(), f);
        for bad in ["\"af\"", "\"00000000000000zz\"", "12"] {
            assert!(serde_json::from_str::<Fingerprint>(bad).is_err(), "{bad}");
        }
    }
}
