//! Scene loading errors.

use thiserror::Error;

/// One problem in a scene: where (a JSON path such as `bodies[3].mass`) and what.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Problem {
    /// Location, e.g. `bodies[3].mass`.
    pub path: String,
    /// What is wrong.
    pub message: String,
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
    /// The scene parsed but has problems; all of them are listed.
    #[error("{} problem(s) in the scene:\n{}", .0.len(), .0.iter().map(|p| format!("  {p}")).collect::<Vec<_>>().join("\n"))]
    Invalid(Vec<Problem>),
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

impl SceneError {
    /// The problems (empty for syntax and I/O errors).
    pub fn problems(&self) -> &[Problem] {
        match self {
            SceneError::Invalid(p) => p,
            _ => &[],
        }
    }
}
