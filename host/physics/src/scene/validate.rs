//! Validation: every problem of a parsed scene, each with its location.

use std::collections::HashMap;

use super::format::{BodyKindDesc, SceneFile, ShapeDesc};
use super::Problem;
use crate::pipeline::Effect;

struct Report(Vec<Problem>);

impl Report {
    fn add(&mut self, path: impl Into<String>, message: impl Into<String>) {
        self.0.push(Problem {
            path: path.into(),
            message: message.into(),
        });
    }

    fn finite3(&mut self, path: &str, v: &[f64; 3]) {
        for (k, x) in v.iter().enumerate() {
            if !x.is_finite() {
                self.add(format!("{path}[{k}]"), format!("must be finite, got {x}"));
            }
        }
    }

    fn positive(&mut self, path: &str, x: f64) {
        if !(x.is_finite() && x > 0.0) {
            self.add(path, format!("must be positive, got {x}"));
        }
    }

    fn non_negative(&mut self, path: &str, x: f64) {
        if !(x.is_finite() && x >= 0.0) {
            self.add(path, format!("must be ≥ 0, got {x}"));
        }
    }
}

impl SceneFile {
    /// Every problem of the scene (empty when it is valid).
    pub fn problems(&self) -> Vec<Problem> {
        let mut r = Report(Vec::new());
        r.positive("dt", self.dt);
        if !(1..=64).contains(&self.solver.substeps) {
            r.add(
                "solver.substeps",
                format!("must be 1 … 64, got {}", self.solver.substeps),
            );
        }
        r.positive("solver.contact_hertz", self.solver.contact_hertz);
        r.non_negative(
            "solver.restitution_threshold",
            self.solver.restitution_threshold,
        );
        r.finite3("gravity", &self.gravity);
        r.non_negative("damping.linear", self.damping.linear);
        r.non_negative("damping.angular", self.damping.angular);

        // Effects: no duplicates, requirements declared.
        let mut seen = HashMap::new();
        for (i, e) in self.effects.iter().enumerate() {
            if let Some(first) = seen.insert(*e, i) {
                r.add(
                    format!("effects[{i}]"),
                    format!("'{}' is already declared at effects[{first}]", e.name()),
                );
            }
        }
        for (i, e) in self.effects.iter().enumerate() {
            for req in e.requires() {
                if !self.effects.contains(req) {
                    r.add(
                        format!("effects[{i}]"),
                        format!("'{}' requires the '{}' effect", e.name(), req.name()),
                    );
                }
            }
        }

        // Materials.
        let mut materials = HashMap::new();
        for (i, m) in self.materials.iter().enumerate() {
            let p = format!("materials[{i}]");
            if m.name.is_empty() {
                r.add(format!("{p}.name"), "must not be empty");
            } else if let Some(j) = materials.insert(m.name.as_str(), i) {
                r.add(
                    format!("{p}.name"),
                    format!("'{}' is already the name of materials[{j}]", m.name),
                );
            }
            r.non_negative(&format!("{p}.friction"), m.friction);
            if !(m.restitution.is_finite() && (0.0..=1.0).contains(&m.restitution)) {
                r.add(
                    format!("{p}.restitution"),
                    format!("must be in [0, 1], got {}", m.restitution),
                );
            }
            r.non_negative(&format!("{p}.rolling_resistance"), m.rolling_resistance);
        }

        // Bodies.
        let mut names: HashMap<&str, usize> = HashMap::new();
        for (i, b) in self.bodies.iter().enumerate() {
            let p = format!("bodies[{i}]");
            if !b.name.is_empty() {
                if let Some(j) = names.insert(b.name.as_str(), i) {
                    r.add(
                        format!("{p}.name"),
                        format!("'{}' is already the name of bodies[{j}]", b.name),
                    );
                }
            }
            let sp = format!("{p}.shape");
            match &b.shape {
                ShapeDesc::Box { half_extents } => {
                    for (k, h) in half_extents.iter().enumerate() {
                        r.positive(&format!("{sp}.half_extents[{k}]"), *h);
                    }
                }
                ShapeDesc::Sphere { radius } => r.positive(&format!("{sp}.radius"), *radius),
                ShapeDesc::Capsule {
                    radius,
                    half_height,
                } => {
                    r.positive(&format!("{sp}.radius"), *radius);
                    r.non_negative(&format!("{sp}.half_height"), *half_height);
                }
                ShapeDesc::Cylinder {
                    radius,
                    half_height,
                } => {
                    r.positive(&format!("{sp}.radius"), *radius);
                    r.positive(&format!("{sp}.half_height"), *half_height);
                }
                ShapeDesc::HalfSpace { normal } => {
                    r.finite3(&format!("{sp}.normal"), normal);
                    let n2: f64 = normal.iter().map(|x| x * x).sum();
                    if n2.is_nan() || n2 <= 1e-24 {
                        r.add(format!("{sp}.normal"), "must be a non-zero vector");
                    }
                    if b.kind == BodyKindDesc::Dynamic {
                        r.add(
                            format!("{p}.kind"),
                            "a half-space is infinite: it must be 'fixed' or 'kinematic'",
                        );
                    }
                }
            }
            match (b.kind, b.mass, b.density) {
                (_, Some(_), Some(_)) => r.add(&p, "give either 'mass' or 'density', not both"),
                (BodyKindDesc::Dynamic, None, None) => {
                    r.add(&p, "a dynamic body needs 'mass' (kg) or 'density' (kg/m³)")
                }
                _ => {}
            }
            if let Some(m) = b.mass {
                r.positive(&format!("{p}.mass"), m);
            }
            if let Some(d) = b.density {
                r.positive(&format!("{p}.density"), d);
            }
            r.finite3(&format!("{p}.position"), &b.position);
            r.finite3(&format!("{p}.rotation"), &b.rotation);
            r.finite3(&format!("{p}.velocity"), &b.velocity);
            r.finite3(&format!("{p}.angular_velocity"), &b.angular_velocity);
            if b.kind == BodyKindDesc::Fixed
                && (b.velocity.iter().any(|x| *x != 0.0)
                    || b.angular_velocity.iter().any(|x| *x != 0.0))
            {
                r.add(
                    format!("{p}.velocity"),
                    "a fixed body cannot move; use kind 'kinematic' for a driven body",
                );
            }
            if let Some(m) = &b.material {
                if !materials.contains_key(m.as_str()) {
                    r.add(format!("{p}.material"), format!("unknown material '{m}'"));
                }
            }
        }

        // Joints.
        if !self.joints.is_empty() && !self.effects.contains(&Effect::Joints) {
            r.add(
                "joints",
                format!(
                    "{} joint(s) given but the 'joints' effect is not declared",
                    self.joints.len()
                ),
            );
        }
        for (j, jd) in self.joints.iter().enumerate() {
            let p = format!("joints[{j}]");
            if !matches!(jd.kind.as_str(), "ball" | "revolute" | "fixed") {
                r.add(
                    format!("{p}.type"),
                    format!("unknown joint type '{}' (ball, revolute, fixed)", jd.kind),
                );
            }
            let lookup = |r: &mut Report, field: &str, name: &str| {
                let i = names.get(name).copied();
                if i.is_none() {
                    r.add(format!("{p}.{field}"), format!("unknown body '{name}'"));
                }
                i
            };
            let b1 = lookup(&mut r, "body1", &jd.body1);
            let b2 = lookup(&mut r, "body2", &jd.body2);
            if let (Some(b1), Some(b2)) = (b1, b2) {
                if b1 == b2 {
                    r.add(&p, format!("joins body '{}' to itself", jd.body1));
                } else if self.bodies[b1].kind != BodyKindDesc::Dynamic
                    && self.bodies[b2].kind != BodyKindDesc::Dynamic
                {
                    r.add(&p, "at least one of the two bodies must be dynamic");
                }
            }
            r.finite3(&format!("{p}.anchor"), &jd.anchor);
            match (&jd.axis, jd.kind.as_str()) {
                (None, "revolute") => r.add(format!("{p}.axis"), "a revolute joint needs an axis"),
                (Some(a), _) => {
                    r.finite3(&format!("{p}.axis"), a);
                    if a.iter().map(|x| x * x).sum::<f64>() < 1e-24 {
                        r.add(format!("{p}.axis"), "must be a non-zero vector");
                    }
                }
                _ => {}
            }
        }

        // Articulated trees.
        if !self.articulated.is_empty() && !self.effects.contains(&Effect::Articulated) {
            r.add(
                "articulated",
                format!(
                    "{} articulated system(s) given but the 'articulated' effect is not declared",
                    self.articulated.len()
                ),
            );
        }
        for (k, a) in self.articulated.iter().enumerate() {
            let p = format!("articulated[{k}].model");
            let mut structural = false;
            for (i, b) in a.model.bodies.iter().enumerate() {
                let bp = format!("{p}.bodies[{i}]");
                if let Some(par) = b.parent {
                    if par >= i {
                        r.add(
                            format!("{bp}.parent"),
                            format!(
                                "unknown parent {par}: must be an earlier body (0 … {})",
                                i as i64 - 1
                            ),
                        );
                        structural = true;
                    }
                }
                r.positive(&format!("{bp}.inertia.mass"), b.inertia.mass);
                if b.inertia.mass <= 0.0 || !b.inertia.mass.is_finite() {
                    structural = true;
                }
                if !matches!(
                    b.joint.kind.as_str(),
                    "revolute"
                        | "prismatic"
                        | "cylindrical"
                        | "universal"
                        | "ball"
                        | "free"
                        | "fixed"
                ) {
                    r.add(
                        format!("{bp}.joint.type"),
                        format!("unknown joint type '{}'", b.joint.kind),
                    );
                    structural = true;
                }
            }
            if structural {
                continue;
            }
            match a.model.build::<f64>() {
                Err(e) => r.add(&p, e.to_string()),
                Ok(tree) => {
                    if let Some(q) = &a.q {
                        if q.len() != tree.nq() {
                            r.add(
                                format!("articulated[{k}].q"),
                                format!(
                                    "has {} values, the model has {} coordinates",
                                    q.len(),
                                    tree.nq()
                                ),
                            );
                        }
                        if q.iter().any(|x| !x.is_finite()) {
                            r.add(format!("articulated[{k}].q"), "must be finite");
                        }
                    }
                    if let Some(qd) = &a.qd {
                        if qd.len() != tree.nv() {
                            r.add(
                                format!("articulated[{k}].qd"),
                                format!(
                                    "has {} values, the model has {} velocities",
                                    qd.len(),
                                    tree.nv()
                                ),
                            );
                        }
                        if qd.iter().any(|x| !x.is_finite()) {
                            r.add(format!("articulated[{k}].qd"), "must be finite");
                        }
                    }
                }
            }
        }
        r.0
    }
}
