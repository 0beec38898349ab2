//! The articulated trees of a scene: each model's gravity, bodies, joints and inertias,
//! and the extras a tree takes in a world (its links' shapes, materials and motors).

use super::*;

impl SceneFile {
    /// The problems of the scene's articulated trees, into `r`.
    pub(super) fn tree_problems(&self, r: &mut Report) {
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
            let before = r.problems.len() + r.more;
            r.bounded3(
                &format!("{p}.gravity"),
                &a.model.gravity,
                limits::GRAVITY_M_S2,
                "m/s²",
            );
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
                r.range(
                    &format!("{bp}.inertia.mass"),
                    b.inertia.mass,
                    limits::MASS_KG,
                    "kg",
                );
                r.coords3(
                    &format!("{bp}.inertia.com"),
                    &b.inertia.com,
                    limits::SIZE_M.1,
                    "m",
                );
                for (c, x) in b.inertia.inertia_com.iter().enumerate() {
                    let ip = format!("{bp}.inertia.inertia_com[{c}]");
                    if !x.is_finite() {
                        r.add(ip, format!("must be finite, got {x}"));
                    } else if x.abs() > limits::INERTIA_KG_M2 {
                        r.add(
                            ip,
                            format!(
                                "must be within {} … {} kg·m², got {}",
                                num(-limits::INERTIA_KG_M2),
                                num(limits::INERTIA_KG_M2),
                                num(*x)
                            ),
                        );
                    }
                }
                r.coords3(
                    &format!("{bp}.placement.translation"),
                    &b.placement.translation,
                    limits::POSITION_M,
                    "m",
                );
                for (row, v) in b.placement.rotation.iter().enumerate() {
                    // Entries of a rotation matrix lie in [-1, 1]; the model checks the rest.
                    r.coords3(
                        &format!("{bp}.placement.rotation[{row}]"),
                        v,
                        1.0 + 1e-6,
                        "",
                    );
                }
                for (field, axis) in [("axis", &b.joint.axis), ("axis2", &b.joint.axis2)] {
                    if let Some(ax) = axis {
                        r.direction(&format!("{bp}.joint.{field}"), ax);
                    }
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
                }
            }
            // The model is only built from numbers that passed.
            structural |= r.problems.len() + r.more != before;
            if structural {
                continue;
            }
            match a.model.build::<f64>() {
                Err(e) => r.add(&p, e.to_string()),
                Ok(tree) => {
                    let vectors = [
                        ("q", &a.q, tree.nq(), "coordinates", limits::TREE_Q),
                        ("qd", &a.qd, tree.nv(), "velocities", limits::TREE_QD),
                    ];
                    for (field, values, n, what, max) in vectors {
                        let Some(values) = values else { continue };
                        let vp = format!("articulated[{k}].{field}");
                        if values.len() != n {
                            r.add(
                                &vp,
                                format!("has {} values, the model has {n} {what}", values.len()),
                            );
                        }
                        if let Some((c, x)) = values
                            .iter()
                            .enumerate()
                            .find(|(_, x)| !(x.is_finite() && x.abs() <= max))
                        {
                            r.add(
                                format!("{vp}[{c}]"),
                                format!(
                                    "must be finite and within {} … {}, got {}",
                                    num(-max),
                                    num(max),
                                    num(*x)
                                ),
                            );
                        }
                    }
                    tree_extras(r, k, a, &tree, &self.materials);
                }
            }
        }
    }
}

/// Checks a tree's link shapes and drives: links and joints that exist, primitive shapes
/// with sizes in range, known materials, drives on additive coordinates with finite settings.
fn tree_extras(
    r: &mut Report,
    k: usize,
    a: &crate::scene::format::ArticulatedDesc,
    tree: &crate::model::ArticulatedTree<f64>,
    materials: &[crate::scene::format::MaterialDesc],
) {
    link_shape_problems(r, k, a, tree, materials);
    drive_problems(r, k, a, tree);
}

/// Checks a tree's link shapes: links that exist, primitive shapes with sizes in range,
/// known materials.
fn link_shape_problems(
    r: &mut Report,
    k: usize,
    a: &crate::scene::format::ArticulatedDesc,
    tree: &crate::model::ArticulatedTree<f64>,
    materials: &[crate::scene::format::MaterialDesc],
) {
    let link = |name: &str| tree.bodies().iter().position(|b| b.name == name);
    for (i, ls) in a.shapes.iter().enumerate() {
        let p = format!("articulated[{k}].shapes[{i}]");
        if link(&ls.link).is_none() {
            r.add(format!("{p}.link"), format!("no link named '{}'", ls.link));
        }
        let sizes: &[f64] = match &ls.shape {
            ShapeDesc::Box { half_extents } => half_extents,
            ShapeDesc::Sphere { radius } => std::slice::from_ref(radius),
            ShapeDesc::Capsule { radius, .. } | ShapeDesc::Cylinder { radius, .. } => {
                std::slice::from_ref(radius)
            }
            ShapeDesc::HalfSpace { .. } | ShapeDesc::Compound { .. } => {
                r.add(
                    format!("{p}.shape"),
                    "a link's shapes are boxes, spheres, capsules or cylinders",
                );
                &[]
            }
        };
        for x in sizes {
            r.range(&format!("{p}.shape"), *x, limits::SIZE_M, "m");
        }
        r.coords3(
            &format!("{p}.position"),
            &ls.position,
            limits::PART_OFFSET_M,
            "m",
        );
        r.bounded3(
            &format!("{p}.rotation"),
            &ls.rotation,
            limits::ROTATION_RAD,
            "rad",
        );
        if let Some(m) = &ls.material {
            if !materials.iter().any(|x| &x.name == m) {
                r.add(format!("{p}.material"), format!("no material named '{m}'"));
            }
        }
    }
}

/// Checks a tree's drives: on links and additive coordinates that exist, with finite
/// settings.
fn drive_problems(
    r: &mut Report,
    k: usize,
    a: &crate::scene::format::ArticulatedDesc,
    tree: &crate::model::ArticulatedTree<f64>,
) {
    let link = |name: &str| tree.bodies().iter().position(|b| b.name == name);
    for (i, d) in a.drives.iter().enumerate() {
        let p = format!("articulated[{k}].drives[{i}]");
        let Some(l) = link(&d.joint) else {
            r.add(
                format!("{p}.joint"),
                format!("no joint (link) named '{}'", d.joint),
            );
            continue;
        };
        let b = &tree.bodies()[l];
        if !matches!(
            b.joint.type_name(),
            "revolute" | "prismatic" | "cylindrical" | "universal"
        ) {
            r.add(
                format!("{p}.joint"),
                format!(
                    "a {} joint cannot be driven: drives act on revolute, prismatic, cylindrical or universal joints",
                    b.joint.type_name()
                ),
            );
        }
        if d.coordinate >= b.nv() {
            r.add(
                format!("{p}.coordinate"),
                format!(
                    "the joint has {} coordinate(s), not {}",
                    b.nv(),
                    d.coordinate + 1
                ),
            );
        }
        if d.motor.is_none() && d.limits.is_none() && d.trajectory.is_none() {
            r.add(&p, "give 'motor', 'limits' or 'trajectory'");
        }
        if d.trajectory.is_some() && (d.motor.is_some() || d.limits.is_some()) {
            r.add(&p, "a prescribed coordinate takes no motor or limits");
        }
        if let Some(m) = &d.motor {
            for (f, x) in [
                ("stiffness", m.stiffness),
                ("damping", m.damping),
                ("max_force", m.max_force),
            ] {
                r.range(&format!("{p}.motor.{f}"), x, (0.0, 1e9), "");
            }
            for (f, x) in [
                ("target_position", m.target_position.unwrap_or(0.0)),
                ("target_velocity", m.target_velocity),
            ] {
                r.range(
                    &format!("{p}.motor.{f}"),
                    x,
                    (-limits::TREE_Q, limits::TREE_Q),
                    "",
                );
            }
        }
        if let Some([lo, hi]) = d.limits {
            if !(lo.is_finite()
                && hi.is_finite()
                && lo < hi
                && lo.abs() <= limits::TREE_Q
                && hi.abs() <= limits::TREE_Q)
            {
                r.add(
                    format!("{p}.limits"),
                    format!("must be finite with lower < upper, got [{lo}, {hi}]"),
                );
            }
        }
        if let Some(t) = &d.trajectory {
            let tp = format!("{p}.trajectory");
            match t {
                crate::scene::format::TrajectoryDesc::ConstantVelocity { start, velocity } => {
                    r.range(
                        &format!("{tp}.start"),
                        *start,
                        (-limits::TREE_Q, limits::TREE_Q),
                        "",
                    );
                    r.range(
                        &format!("{tp}.velocity"),
                        *velocity,
                        (-limits::TREE_QD, limits::TREE_QD),
                        "",
                    );
                }
                crate::scene::format::TrajectoryDesc::Keyframes { points } => {
                    if points.is_empty() || points.len() > 10_000 {
                        r.add(
                            format!("{tp}.points"),
                            format!("needs 1 … 10000 points, has {}", points.len()),
                        );
                    }
                    let ok = points.iter().all(|p| {
                        p[0].is_finite() && p[1].is_finite() && p[1].abs() <= limits::TREE_Q
                    }) && points.windows(2).all(|w| w[0][0] < w[1][0]);
                    if !ok {
                        r.add(
                            format!("{tp}.points"),
                            "times must increase and every value be finite",
                        );
                    }
                }
                crate::scene::format::TrajectoryDesc::Sinusoid {
                    offset,
                    amplitude,
                    frequency,
                    phase,
                } => {
                    r.range(
                        &format!("{tp}.offset"),
                        *offset,
                        (-limits::TREE_Q, limits::TREE_Q),
                        "",
                    );
                    r.range(
                        &format!("{tp}.amplitude"),
                        *amplitude,
                        (-limits::TREE_Q, limits::TREE_Q),
                        "",
                    );
                    r.range(&format!("{tp}.frequency"), *frequency, (0.0, 1e3), "Hz");
                    r.range(
                        &format!("{tp}.phase"),
                        *phase,
                        (-limits::ROTATION_RAD, limits::ROTATION_RAD),
                        "rad",
                    );
                }
            }
        }
    }
}
