//! The JSON model description, shared by the Rust side and the peer scripts
//! (`peers/pinocchio_fixtures.py`), so that every model is defined once.
//!
//! ```json
//! { "name": "chain7", "gravity": [0, 0, -9.81],
//!   "bodies": [ { "name": "link0", "parent": null,
//!                 "joint": { "type": "revolute", "axis": [1, 0, 0] },
//!                 "placement": { "rotation": [[1,0,0],[0,1,0],[0,0,1]], "translation": [0,0,0] },
//!                 "inertia": { "mass": 1.0, "com": [0,0,0.1],
//!                              "inertia_com": [0.01,0.02,0.03, 0,0,0] } } ] }
//! ```
//! `rotation` is row-major; `inertia_com` = `[xx, yy, zz, xy, xz, yz]` about the centre of
//! mass in body axes (kg·m²); `parent` is the index of an earlier body or `null` (world).
//! Joint types and their coordinates: see [`crate::model::joints`].

use serde::{Deserialize, Serialize};

measure_use!(super::joint_description::JointDescription);
use super::joints::from_description;
use super::{ArticulatedTree, ModelError};
use crate::algebra::{Inertia, Mat3, Sym3, Vec3, SE3};
use crate::Real;

measure_pub_fields! {
    /// A rigid transform: row-major rotation and translation (m).
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    measure struct PlacementDescription {
        /// Rotation matrix, rows.
        rotation: [[f64; 3]; 3],
        /// Translation (m).
        translation: [f64; 3],
    }
}

measure_pub_fields! {
    /// Mass properties.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    measure struct InertiaDescription {
        /// Mass (kg).
        mass: f64,
        /// Centre of mass in the body frame (m).
        com: [f64; 3],
        /// Rotational inertia about the centre of mass, body axes, `[xx, yy, zz, xy, xz, yz]` (kg·m²).
        inertia_com: [f64; 6],
    }
}

measure_pub_fields! {
    /// One body.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    measure struct BodyDescription {
        /// Name.
        name: String,
        /// Parent body index, `None` for the world.
        parent: Option<usize>,
        /// The joint to the parent.
        joint: JointDescription,
        /// Joint frame in the parent frame.
        placement: PlacementDescription,
        /// Mass properties in the body frame.
        inertia: InertiaDescription,
    }
}

measure_pub_fields! {
    /// A whole articulated tree.
    #[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
    pub struct ModelDescription {
        /// Model name.
        name: String,
        /// Gravity, world frame (m/s²).
        gravity: [f64; 3],
        /// Bodies, parents first.
        bodies: Vec<BodyDescription>,
    }
}

fn v3<T: Real>(a: [f64; 3]) -> Vec3<T> {
    Vec3::new(T::from_f64(a[0]), T::from_f64(a[1]), T::from_f64(a[2]))
}

fn a3<T: Real>(v: &Vec3<T>) -> [f64; 3] {
    [v.x.to_f64(), v.y.to_f64(), v.z.to_f64()]
}

impl ModelDescription {
    /// Parses JSON.
    pub fn from_json(s: &str) -> Result<Self, ModelError> {
        Ok(serde_json::from_str(s)?)
    }

    /// Pretty JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("model description serialises")
    }

    /// Builds the tree.
    pub fn build<T: Real>(&self) -> Result<ArticulatedTree<T>, ModelError> {
        let mut tree = ArticulatedTree::new(v3(self.gravity));
        for b in &self.bodies {
            let r = &b.placement.rotation;
            let rot = Mat3::new(
                T::from_f64(r[0][0]),
                T::from_f64(r[0][1]),
                T::from_f64(r[0][2]),
                T::from_f64(r[1][0]),
                T::from_f64(r[1][1]),
                T::from_f64(r[1][2]),
                T::from_f64(r[2][0]),
                T::from_f64(r[2][1]),
                T::from_f64(r[2][2]),
            );
            let placement = SE3::new(rot, v3(b.placement.translation));
            let i = &b.inertia.inertia_com;
            let c = |k: usize| T::from_f64(i[k]);
            let inertia = Inertia::from_com(
                T::from_f64(b.inertia.mass),
                v3(b.inertia.com),
                Sym3::new(c(0), c(1), c(2), c(3), c(4), c(5)),
            );
            tree.add_boxed(
                b.name.clone(),
                b.parent,
                placement,
                from_description(&b.joint)?,
                inertia,
            )?;
        }
        Ok(tree)
    }

    /// Describes an existing tree.
    pub fn of<T: Real>(name: &str, tree: &ArticulatedTree<T>) -> Self {
        let bodies = tree
            .bodies()
            .iter()
            .map(|b| {
                let r = &b.placement.r;
                let row = |i: usize| [r[(i, 0)].to_f64(), r[(i, 1)].to_f64(), r[(i, 2)].to_f64()];
                let ic = b.inertia.i_com();
                BodyDescription {
                    name: b.name.clone(),
                    parent: b.parent,
                    joint: b.joint.describe(),
                    placement: PlacementDescription {
                        rotation: [row(0), row(1), row(2)],
                        translation: a3(&b.placement.p),
                    },
                    inertia: InertiaDescription {
                        mass: b.inertia.m.to_f64(),
                        com: a3(&b.inertia.com()),
                        inertia_com: [
                            ic.xx.to_f64(),
                            ic.yy.to_f64(),
                            ic.zz.to_f64(),
                            ic.xy.to_f64(),
                            ic.xz.to_f64(),
                            ic.yz.to_f64(),
                        ],
                    },
                }
            })
            .collect();
        Self {
            name: name.to_string(),
            gravity: a3(&tree.gravity()),
            bodies,
        }
    }
}
