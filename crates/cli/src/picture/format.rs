//! Which files a picture is written as, and its bytes for each.

use super::canvas::Canvas;

/// Which files a picture is written as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Format {
    Svg,
    Png,
    Both,
}

impl Format {
    /// The file extensions, in writing order.
    pub fn extensions(self) -> &'static [&'static str] {
        match self {
            Format::Svg => &["svg"],
            Format::Png => &["png"],
            Format::Both => &["svg", "png"],
        }
    }

    /// The picture encoded for a file of extension `ext`.
    pub fn encode(canvas: &Canvas, ext: &str) -> Result<Vec<u8>, String> {
        if ext == "png" {
            canvas.png()
        } else {
            Ok(canvas.svg().into_bytes())
        }
    }
}
