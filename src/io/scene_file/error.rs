//! [`SceneFileError`]: why a scene file could not be read or built, located by file and line.

use std::fmt;
use std::path::PathBuf;

use crate::error::ShapeError;
use crate::sim::SimError;

/// Why a scene file could not be read or built. Its message starts with the file (when read
/// from one) and the line (when known), then names the item and the field.
///
/// ```
/// use spheresweep::io::scene_file::{SceneFile, SceneFileError};
/// let text = "[run]\nt_end = 1\n[[sphere]]\ncentre = [0, 0, 0]\nradius = 1\nmaterial = \"rubber\"\n";
/// let err = SceneFile::from_toml_str(text)?.build().unwrap_err();
/// assert!(matches!(&err, SceneFileError::Item { line: Some(6), item, .. } if item == "sphere 0"));
/// let message = r#"line 6: sphere 0: material "rubber" is not declared (declared: "default")"#;
/// assert_eq!(err.to_string(), message);
/// # Ok::<(), spheresweep::io::scene_file::SceneFileError>(())
/// ```
#[derive(Debug)]
#[non_exhaustive]
pub enum SceneFileError {
    /// The file could not be read.
    Read {
        /// The path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The text is not valid TOML or JSON, or does not fit the format (a typo'd field, a
    /// wrong type, a missing required field). The message is the parser's: it names the line,
    /// the column and the key.
    Syntax {
        /// The file, if read from one.
        file: Option<PathBuf>,
        /// The parser's message.
        message: String,
    },
    /// An item that parsed but does not make sense (an undeclared material, a field that does
    /// not belong to its generator, a value out of range).
    Item {
        /// The file, if read from one.
        file: Option<PathBuf>,
        /// The line of the item or field (TOML only).
        line: Option<usize>,
        /// The item (`"sphere 3"`, `"generate 1 (nozzle)"`, `"boundary"`).
        item: String,
        /// What is wrong.
        problem: String,
    },
    /// The simulation refused an item (overlapping spheres, a generator's parameters).
    Sim {
        /// The file, if read from one.
        file: Option<PathBuf>,
        /// The line of the (first) item named.
        line: Option<usize>,
        /// The item or items.
        item: String,
        /// The simulation's error.
        source: SimError,
    },
    /// A shape's constructor refused an item.
    Shape {
        /// The file, if read from one.
        file: Option<PathBuf>,
        /// The line of the item or field.
        line: Option<usize>,
        /// The item (`"plane 0"`).
        item: String,
        /// The constructor's error.
        source: ShapeError,
    },
}

impl fmt::Display for SceneFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let at = |f: &mut fmt::Formatter<'_>, file: &Option<PathBuf>, line: &Option<usize>| {
            f.write_str(&location(file.as_deref(), *line))
        };
        match self {
            SceneFileError::Read { path, source } => {
                write!(f, "cannot read {}: {source}", path.display())
            }
            SceneFileError::Syntax { file, message } => {
                at(f, file, &None)?;
                f.write_str(message.trim_end())
            }
            SceneFileError::Item {
                file,
                line,
                item,
                problem,
            } => {
                at(f, file, line)?;
                write!(f, "{item}: {problem}")
            }
            SceneFileError::Sim {
                file,
                line,
                item,
                source,
            } => {
                at(f, file, line)?;
                write!(f, "{item}: {source}")
            }
            SceneFileError::Shape {
                file,
                line,
                item,
                source,
            } => {
                at(f, file, line)?;
                write!(f, "{item}: {source}")
            }
        }
    }
}

impl std::error::Error for SceneFileError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SceneFileError::Read { source, .. } => Some(source),
            SceneFileError::Sim { source, .. } => Some(source),
            SceneFileError::Shape { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// `FILE:LINE: `, `FILE: `, `line LINE: ` or nothing: where an item of a scene file is, as its
/// errors and warnings begin.
pub(super) fn location(file: Option<&std::path::Path>, line: Option<usize>) -> String {
    match (file, line) {
        (Some(p), Some(l)) => format!("{}:{l}: ", p.display()),
        (Some(p), None) => format!("{}: ", p.display()),
        (None, Some(l)) => format!("line {l}: "),
        (None, None) => String::new(),
    }
}
