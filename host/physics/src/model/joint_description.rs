//! A joint as the JSON model description names it: its type and axes
//! (`model/description.rs` holds the rest of a model; the joint types themselves are in
//! `model/joints/`).

use serde::{Deserialize, Serialize};

/// A joint: its type name and axes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct JointDescription {
    /// Type name (`revolute`, `prismatic`, `cylindrical`, `universal`, `ball`, `free`, `fixed`).
    #[serde(rename = "type")]
    pub kind: String,
    /// The (first) axis, joint frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<[f64; 3]>,
    /// The second axis (universal joint).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis2: Option<[f64; 3]>,
}

impl JointDescription {
    /// A joint type without axes.
    pub fn new(kind: &str) -> Self {
        Self {
            kind: kind.to_string(),
            axis: None,
            axis2: None,
        }
    }

    /// A joint type with one axis.
    pub(crate) fn with_axis(kind: &str, axis: [f64; 3]) -> Self {
        Self {
            axis: Some(axis),
            ..Self::new(kind)
        }
    }
}
