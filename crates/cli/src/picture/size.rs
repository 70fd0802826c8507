//! A picture size in pixels, as `--size WIDTHxHEIGHT` gives it, within limits.

/// A picture size in pixels, parsed from `WIDTHxHEIGHT`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

impl Size {
    /// Smallest and largest side accepted, and the most pixels.
    pub const MIN: (u32, u32) = (160, 120);
    pub const MAX_SIDE: u32 = 8192;
    pub const MAX_PIXELS: u64 = 40_000_000;
}

impl std::str::FromStr for Size {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        let bad = |why: &str| format!("{s:?} is not a picture size: {why}");
        let (w, h) = s
            .split_once(['x', 'X', '×'])
            .ok_or_else(|| bad("give WIDTHxHEIGHT in pixels, e.g. 1600x800"))?;
        let side = |v: &str, name: &str, min: u32| -> Result<u32, String> {
            let n: u32 = v
                .trim()
                .parse()
                .map_err(|_| bad(&format!("the {name} {v:?} is not a whole number")))?;
            if n < min || n > Self::MAX_SIDE {
                return Err(bad(&format!(
                    "the {name} must be between {min} and {} pixels",
                    Self::MAX_SIDE
                )));
            }
            Ok(n)
        };
        let size = Self {
            width: side(w, "width", Self::MIN.0)?,
            height: side(h, "height", Self::MIN.1)?,
        };
        if u64::from(size.width) * u64::from(size.height) > Self::MAX_PIXELS {
            return Err(bad(&format!("more than {} pixels", Self::MAX_PIXELS)));
        }
        Ok(size)
    }
}

impl std::fmt::Display for Size {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}x{}", self.width, self.height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_bad_ones_say_why() {
        assert_eq!(
            "1600x800".parse::<Size>(),
            Ok(Size {
                width: 1600,
                height: 800
            })
        );
        assert_eq!(
            "640×480".parse::<Size>().map(|s| s.to_string()),
            Ok("640x480".into())
        );
        for (bad, why) in [
            ("1600", "WIDTHxHEIGHT"),
            ("0x600", "between 160 and 8192"),
            ("axb", "not a whole number"),
            ("-5x100", "not a whole number"),
            ("8192x8192", "more than"),
        ] {
            let e = bad.parse::<Size>().unwrap_err();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }
}
