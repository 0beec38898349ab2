//! Scene loading errors.

use thiserror::Error;

/// One problem in a scene: where (a JSON path such as `bodies[3].mass`) and what.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// Location, e.g. `bodies[3].mass`.
    pub(crate) path: String,
    /// What is wrong.
    pub(crate) message: String,
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path, self.message)
    }
}

/// Why a scene could not be loaded.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The text is not JSON of the scene's shape (first such error, with line and column).
    #[error("scene is not valid JSON for the format: {0}")]
    Syntax(String),
    /// The scene parsed but has problems; all of them are listed, on one line.
    #[error("{}", invalid_message(.0))]
    Invalid(Vec<Problem>),
    /// A list of the scene (bodies, shapes, joints, materials, trees, tree bodies) is longer
    /// than its limit; found while reading, before the list was built.
    #[error("{path}: at least {at_least} {what}, more than the limit of {limit}")]
    TooMany {
        /// The list, e.g. `bodies` or `articulated[2].model.bodies`.
        path: String,
        /// What its entries are.
        what: &'static str,
        /// How many were counted before reading stopped (the limit + 1).
        at_least: usize,
        /// The limit.
        limit: usize,
    },
    /// The scene text is larger than the limit (bytes).
    #[error("scene text of {bytes} bytes or more is larger than the limit of {limit} bytes")]
    TooLarge {
        /// Its size, or the bytes read before stopping (bytes).
        bytes: u64,
        /// The limit (bytes).
        limit: u64,
    },
    /// A file could not be read.
    #[error("cannot read scene file {path}: {source}")]
    Io {
        /// File.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// No built-in scene of that name.
    #[error("no built-in scene named '{0}' (known: {1})")]
    UnknownBuiltin(String, String),
}

/// One line: a command line prints it as it is.
fn invalid_message(problems: &[Problem]) -> String {
    match problems {
        [one] => format!("invalid scene: {one}"),
        _ => format!(
            "{} problems in the scene: {}",
            problems.len(),
            problems
                .iter()
                .map(|p| p.to_string())
                .collect::<Vec<_>>()
                .join("; ")
        ),
    }
}

impl SceneError {
    /// The problems (empty for syntax and I/O errors).
    pub fn problems(&self) -> &[Problem] {
        match self {
            SceneError::Invalid(p) => p,
            _ => &[],
        }
    }
}
