//! Validation: every problem of a parsed scene, each with its location, and the limits that
//! keep a scene's numbers physical and its memory bounded.
//!
//! Every number is checked to be finite and inside the range of [`limits`] (the scene format
//! section of `docs/physics/scenes-contacts-stacking.md` explains each range). Counts are checked twice: on the JSON
//! text, before serde builds any list ([`check_counts`], [`read_bounded`]), and on the
//! parsed scene, for scenes built in code.

use std::collections::HashMap;
use std::io::Read;

use super::format::{BodyKindDesc, SceneFile, ShapeDesc};
use super::{Problem, SceneError};
use crate::pipeline::Effect;

mod text_counts;
mod trees;
pub(crate) use text_counts::{check_counts, read_bounded, read_file};

/// The ranges a scene's numbers must lie in (SI units), and the most entries of each list.
///
/// The reasons are in the scene format section of `docs/physics/scenes-contacts-stacking.md`; in short, each range
/// holds every physical scene with a wide margin, and keeps the products the step computes
/// (`v·dt`, `ω²·I`, `m·g`) far from overflow and the sizes far above rounding.
pub mod limits {
    /// Sizes: half extents, radii, half heights (m).
    pub(crate) const SIZE_M: (f64, f64) = (1e-4, 1e4);
    /// Masses, given or from density × volume (kg).
    pub(crate) const MASS_KG: (f64, f64) = (1e-6, 1e6);
    /// Densities (kg/m³).
    pub(crate) const DENSITY_KG_M3: (f64, f64) = (1e-2, 1e5);
    /// Largest entry of an articulated body's rotational inertia (kg·m²): the heaviest mass
    /// at the largest size, `1e6 kg × (1e4 m)²`.
    pub(crate) const INERTIA_KG_M2: f64 = 1e14;
    /// Largest coordinate of a position, an anchor or a tree's joint placement (m).
    pub(crate) const POSITION_M: f64 = 1e5;
    /// Largest speed (m/s).
    pub(crate) const SPEED_M_S: f64 = 1e3;
    /// Largest angular speed (rad/s).
    pub(crate) const ANGULAR_SPEED_RAD_S: f64 = 1e4;
    /// Largest angle of a rotation vector (rad).
    pub(crate) const ROTATION_RAD: f64 = 1e3;
    /// The step (s).
    pub(crate) const DT_S: (f64, f64) = (1e-6, 0.1);
    /// Largest gravity (m/s²).
    pub(crate) const GRAVITY_M_S2: f64 = 1e3;
    /// Length of a half-space normal or a joint axis (–; they are normalised).
    pub(crate) const DIRECTION_NORM: (f64, f64) = (1e-6, 1e6);
    /// Contact stiffness (Hz).
    pub(crate) const CONTACT_HERTZ: (f64, f64) = (1e-2, 1e5);
    /// Largest damping rate (1/s).
    pub(crate) const DAMPING_PER_S: f64 = 1e6;
    /// Largest friction coefficient (–).
    pub(crate) const FRICTION: f64 = 10.0;
    /// Largest rolling-resistance coefficient (–).
    pub(crate) const ROLLING_RESISTANCE: f64 = 10.0;
    /// Largest articulated coordinate (m or rad).
    pub(crate) const TREE_Q: f64 = 1e5;
    /// Largest articulated velocity (m/s or rad/s).
    pub(crate) const TREE_QD: f64 = 1e4;
    /// Steps of `vphys run` (`steps`).
    pub(crate) const STEPS: (u64, u64) = (1, 100_000_000);
    /// Most free bodies.
    pub(crate) const BODIES: usize = 100_000;
    /// Most shapes, all bodies together.
    pub(crate) const SHAPES: usize = 100_000;
    /// Most parts of one compound shape.
    pub(crate) const PARTS: usize = 256;
    /// Largest offset of a compound's part from the body's reference frame (m, each coordinate).
    pub(crate) const PART_OFFSET_M: f64 = 1e4;
    /// Most joints.
    pub(crate) const JOINTS: usize = 100_000;
    /// Most materials.
    pub(crate) const MATERIALS: usize = 10_000;
    /// Most articulated trees.
    pub(crate) const TREES: usize = 1_000;
    /// Most bodies (links) in one articulated tree.
    pub(crate) const TREE_LINKS: usize = 1_000;
    /// Most bodies in all articulated trees together.
    pub(crate) const ALL_TREE_LINKS: usize = 100_000;
    /// Most bytes of scene text.
    pub(crate) const SCENE_BYTES: usize = 64 << 20;
}

/// Most problems listed; the rest are counted.
const MAX_PROBLEMS: usize = 50;

/// A number as people write it: plain in `1e-3 … 1e4`, scientific outside.
pub(crate) fn num(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-3..1e4).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// ` unit`, or nothing for a pure number.
fn sfx(unit: &str) -> String {
    if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    }
}

struct Report {
    problems: Vec<Problem>,
    more: usize,
}

impl Report {
    fn add(&mut self, path: impl Into<String>, message: impl Into<String>) {
        if self.problems.len() < MAX_PROBLEMS {
            self.problems.push(Problem {
                path: path.into(),
                message: message.into(),
            });
        } else {
            self.more += 1;
        }
    }

    fn finish(mut self) -> Vec<Problem> {
        if self.more > 0 {
            let more = self.more;
            self.problems.push(Problem {
                path: "scene".into(),
                message: format!("{more} more problem(s) not listed"),
            });
        }
        self.problems
    }

    /// Finite and in `lo … hi`.
    fn range(&mut self, path: &str, x: f64, (lo, hi): (f64, f64), unit: &str) {
        if !(x.is_finite() && x >= lo && x <= hi) {
            self.add(
                path,
                format!(
                    "must be within {} … {}{}, got {}",
                    num(lo),
                    num(hi),
                    sfx(unit),
                    num(x)
                ),
            );
        }
    }

    /// Finite and in `0 … hi`.
    fn non_negative(&mut self, path: &str, x: f64, hi: f64, unit: &str) {
        self.range(path, x, (0.0, hi), unit);
    }

    /// Each component finite and within `±max`, and the length at most `max`.
    fn bounded3(&mut self, path: &str, v: &[f64; 3], max: f64, unit: &str) {
        let mut ok = true;
        for (k, x) in v.iter().enumerate() {
            if !x.is_finite() {
                self.add(format!("{path}[{k}]"), format!("must be finite, got {x}"));
                ok = false;
            } else if x.abs() > max {
                self.add(
                    format!("{path}[{k}]"),
                    format!(
                        "must be within {} … {}{}, got {}",
                        num(-max),
                        num(max),
                        sfx(unit),
                        num(*x)
                    ),
                );
                ok = false;
            }
        }
        if ok {
            let n = norm(v);
            if n > max {
                self.add(
                    path,
                    format!(
                        "length must be at most {}{}, got {}",
                        num(max),
                        sfx(unit),
                        num(n)
                    ),
                );
            }
        }
    }

    /// Each component finite and within `±max` (no length bound: positions and anchors).
    fn coords3(&mut self, path: &str, v: &[f64; 3], max: f64, unit: &str) {
        for (k, x) in v.iter().enumerate() {
            if !x.is_finite() {
                self.add(format!("{path}[{k}]"), format!("must be finite, got {x}"));
            } else if x.abs() > max {
                self.add(
                    format!("{path}[{k}]"),
                    format!(
                        "must be within {} … {}{}, got {}",
                        num(-max),
                        num(max),
                        sfx(unit),
                        num(*x)
                    ),
                );
            }
        }
    }

    /// A direction (normalised later): finite, length in [`limits::DIRECTION_NORM`].
    fn direction(&mut self, path: &str, v: &[f64; 3]) {
        let (lo, hi) = limits::DIRECTION_NORM;
        if v.iter().any(|x| !x.is_finite()) {
            for (k, x) in v.iter().enumerate() {
                if !x.is_finite() {
                    self.add(format!("{path}[{k}]"), format!("must be finite, got {x}"));
                }
            }
            return;
        }
        // Scaled, so that 1e300 does not overflow the square.
        let n = norm(v);
        if n == 0.0 {
            self.add(path, "must be a non-zero vector");
        } else if !(lo..=hi).contains(&n) {
            self.add(
                path,
                format!(
                    "must be a non-zero vector of length {} … {}, got length {}",
                    num(lo),
                    num(hi),
                    num(n)
                ),
            );
        }
    }
}

/// Length of a finite vector without overflow or underflow of the squares.
fn norm(v: &[f64; 3]) -> f64 {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    m * v.iter().map(|x| (x / m) * (x / m)).sum::<f64>().sqrt()
}

/// Volume of a finite shape (m³), `None` for a half-space.
fn volume(shape: &ShapeDesc) -> Option<f64> {
    use std::f64::consts::PI;
    Some(match *shape {
        ShapeDesc::Box { half_extents: h } => 8.0 * h[0] * h[1] * h[2],
        ShapeDesc::Sphere { radius: r } => 4.0 / 3.0 * PI * r * r * r,
        ShapeDesc::Capsule {
            radius: r,
            half_height: h,
        } => PI * r * r * (2.0 * h + 4.0 / 3.0 * r),
        ShapeDesc::Cylinder {
            radius: r,
            half_height: h,
        } => PI * r * r * 2.0 * h,
        ShapeDesc::HalfSpace { .. } => return None,
        ShapeDesc::Compound { ref parts } => {
            let mut total = 0.0;
            for p in parts {
                total += volume(&p.shape)?;
            }
            total
        }
    })
}

/// Shapes in a shape: 1, and a compound's parts besides.
fn shape_count(shape: &ShapeDesc) -> usize {
    match shape {
        ShapeDesc::Compound { parts } => {
            1 + parts.iter().map(|p| shape_count(&p.shape)).sum::<usize>()
        }
        _ => 1,
    }
}

fn count_problem(path: &str, what: &str, count: usize, limit: usize) -> Problem {
    Problem {
        path: path.into(),
        message: format!("{count} {what}, more than the limit of {limit}"),
    }
}

impl SceneFile {
    /// The counts of the scene's lists against [`limits`]; the first that is too long.
    fn count_problem(&self) -> Option<Problem> {
        let links: usize = self.articulated.iter().map(|a| a.model.bodies.len()).sum();
        let lists = [
            ("bodies", "bodies", self.bodies.len(), limits::BODIES),
            (
                "bodies",
                "shapes",
                self.bodies.iter().map(|b| shape_count(&b.shape)).sum(),
                limits::SHAPES,
            ),
            ("joints", "joints", self.joints.len(), limits::JOINTS),
            (
                "materials",
                "materials",
                self.materials.len(),
                limits::MATERIALS,
            ),
            (
                "articulated",
                "articulated trees",
                self.articulated.len(),
                limits::TREES,
            ),
            ("articulated", "tree bodies", links, limits::ALL_TREE_LINKS),
        ];
        for (path, what, n, limit) in lists {
            if n > limit {
                return Some(count_problem(path, what, n, limit));
            }
        }
        self.articulated.iter().enumerate().find_map(|(k, a)| {
            (a.model.bodies.len() > limits::TREE_LINKS).then(|| {
                count_problem(
                    &format!("articulated[{k}].model.bodies"),
                    "bodies",
                    a.model.bodies.len(),
                    limits::TREE_LINKS,
                )
            })
        })
    }

    /// Every problem of the scene (empty when it is valid; at most 50 are listed, then a
    /// count of the others). A list longer than its limit in [`limits`] is the only problem
    /// reported.
    pub fn problems(&self) -> Vec<Problem> {
        if let Some(p) = self.count_problem() {
            return vec![p];
        }
        let mut r = Report {
            problems: Vec::new(),
            more: 0,
        };
        r.range("dt", self.dt, limits::DT_S, "s");
        if let Some(n) = self.steps {
            let (lo, hi) = limits::STEPS;
            if !(lo..=hi).contains(&n) {
                r.add("steps", format!("must be within {lo} … {hi}, got {n}"));
            }
        }
        if !(1..=64).contains(&self.solver.substeps) {
            r.add(
                "solver.substeps",
                format!("must be 1 … 64, got {}", self.solver.substeps),
            );
        }
        r.range(
            "solver.contact_hertz",
            self.solver.contact_hertz,
            limits::CONTACT_HERTZ,
            "Hz",
        );
        r.non_negative(
            "solver.restitution_threshold",
            self.solver.restitution_threshold,
            limits::SPEED_M_S,
            "m/s",
        );
        r.bounded3("gravity", &self.gravity, limits::GRAVITY_M_S2, "m/s²");
        r.non_negative(
            "damping.linear",
            self.damping.linear,
            limits::DAMPING_PER_S,
            "1/s",
        );
        r.non_negative(
            "damping.angular",
            self.damping.angular,
            limits::DAMPING_PER_S,
            "1/s",
        );

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
            r.non_negative(&format!("{p}.friction"), m.friction, limits::FRICTION, "");
            r.range(&format!("{p}.restitution"), m.restitution, (0.0, 1.0), "");
            r.non_negative(
                &format!("{p}.rolling_resistance"),
                m.rolling_resistance,
                limits::ROLLING_RESISTANCE,
                "",
            );
        }

        let names = self.body_problems(&mut r, &materials);

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
            validate_joint(&mut r, &p, jd);
        }

        self.tree_problems(&mut r);
        r.finish()
    }

    /// The problems of the scene's bodies, into `r` (`materials`: the declared
    /// materials' indices by name); returns the named bodies' indices by name.
    fn body_problems<'a>(
        &'a self,
        r: &mut Report,
        materials: &HashMap<&str, usize>,
    ) -> HashMap<&'a str, usize> {
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
            let mut sizes_ok = true;
            let mut size = |r: &mut Report, path: String, x: f64| {
                let before = r.problems.len() + r.more;
                r.range(&path, x, limits::SIZE_M, "m");
                sizes_ok &= r.problems.len() + r.more == before;
            };
            match &b.shape {
                ShapeDesc::Box { half_extents } => {
                    for (k, h) in half_extents.iter().enumerate() {
                        size(r, format!("{sp}.half_extents[{k}]"), *h);
                    }
                }
                ShapeDesc::Sphere { radius } => size(r, format!("{sp}.radius"), *radius),
                ShapeDesc::Capsule {
                    radius,
                    half_height,
                } => {
                    size(r, format!("{sp}.radius"), *radius);
                    // Zero is a sphere.
                    if *half_height != 0.0 {
                        size(r, format!("{sp}.half_height"), *half_height);
                    }
                }
                ShapeDesc::Cylinder {
                    radius,
                    half_height,
                } => {
                    size(r, format!("{sp}.radius"), *radius);
                    size(r, format!("{sp}.half_height"), *half_height);
                }
                ShapeDesc::HalfSpace { normal } => {
                    r.direction(&format!("{sp}.normal"), normal);
                    if b.kind == BodyKindDesc::Dynamic {
                        r.add(
                            format!("{p}.kind"),
                            "a half-space is infinite: it must be 'fixed' or 'kinematic'",
                        );
                    }
                }
                ShapeDesc::Compound { parts } => {
                    sizes_ok &= compound_parts(r, &sp, parts, b, &self.materials);
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
                r.range(&format!("{p}.mass"), m, limits::MASS_KG, "kg");
            }
            if let Some(d) = b.density {
                let before = r.problems.len() + r.more;
                r.range(&format!("{p}.density"), d, limits::DENSITY_KG_M3, "kg/m³");
                let density_ok = r.problems.len() + r.more == before;
                if let (true, true, None, Some(volume)) =
                    (density_ok, sizes_ok, b.mass, volume(&b.shape))
                {
                    let m = d * volume;
                    let (lo, hi) = limits::MASS_KG;
                    if !(lo..=hi).contains(&m) {
                        r.add(
                            format!("{p}.density"),
                            format!(
                                "gives a mass of {} kg (density × volume), outside {} … {} kg",
                                num(m),
                                num(lo),
                                num(hi)
                            ),
                        );
                    }
                }
            }
            r.coords3(
                &format!("{p}.position"),
                &b.position,
                limits::POSITION_M,
                "m",
            );
            r.bounded3(
                &format!("{p}.rotation"),
                &b.rotation,
                limits::ROTATION_RAD,
                "rad",
            );
            r.bounded3(
                &format!("{p}.velocity"),
                &b.velocity,
                limits::SPEED_M_S,
                "m/s",
            );
            r.bounded3(
                &format!("{p}.angular_velocity"),
                &b.angular_velocity,
                limits::ANGULAR_SPEED_RAD_S,
                "rad/s",
            );
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
        names
    }
}

impl SceneFile {
    /// Reads, parses and validates a scene from `reader` (JSON): its lists are counted
    /// while reading and the text is bounded ([`limits`]), so an oversized scene is refused
    /// before anything is built for it.
    pub fn from_reader(reader: impl Read) -> Result<Self, SceneError> {
        let text = read_bounded(reader, "<reader>")?;
        Self::from_json(&text)
    }
}

/// Checks a compound's parts: 1 … [`limits::PARTS`] primitives with sizes, poses, masses and
/// materials in range. `false` when a size is out of range.
fn compound_parts(
    r: &mut Report,
    sp: &str,
    parts: &[super::format::PartShapeDesc],
    body: &super::format::BodyDesc,
    materials: &[super::format::MaterialDesc],
) -> bool {
    if parts.is_empty() || parts.len() > limits::PARTS {
        r.add(
            format!("{sp}.parts"),
            format!(
                "a compound has 1 … {} parts, not {}",
                limits::PARTS,
                parts.len()
            ),
        );
    }
    let mut ok = true;
    for (k, part) in parts.iter().enumerate() {
        let pp = format!("{sp}.parts[{k}]");
        let mut size = |r: &mut Report, path: String, x: f64| {
            let before = r.problems.len() + r.more;
            r.range(&path, x, limits::SIZE_M, "m");
            ok &= r.problems.len() + r.more == before;
        };
        match &part.shape {
            ShapeDesc::Box { half_extents } => {
                for (i, h) in half_extents.iter().enumerate() {
                    size(r, format!("{pp}.shape.half_extents[{i}]"), *h);
                }
            }
            ShapeDesc::Sphere { radius } => size(r, format!("{pp}.shape.radius"), *radius),
            ShapeDesc::Capsule {
                radius,
                half_height,
            } => {
                size(r, format!("{pp}.shape.radius"), *radius);
                if *half_height != 0.0 {
                    size(r, format!("{pp}.shape.half_height"), *half_height);
                }
            }
            ShapeDesc::Cylinder {
                radius,
                half_height,
            } => {
                size(r, format!("{pp}.shape.radius"), *radius);
                size(r, format!("{pp}.shape.half_height"), *half_height);
            }
            ShapeDesc::HalfSpace { .. } | ShapeDesc::Compound { .. } => r.add(
                format!("{pp}.shape"),
                "a compound's parts are boxes, spheres, capsules or cylinders",
            ),
        }
        r.coords3(
            &format!("{pp}.position"),
            &part.position,
            limits::PART_OFFSET_M,
            "m",
        );
        r.bounded3(
            &format!("{pp}.rotation"),
            &part.rotation,
            limits::ROTATION_RAD,
            "rad",
        );
        if part.mass.is_some() && part.density.is_some() {
            r.add(&pp, "give either 'mass' or 'density', not both");
        }
        if let Some(m) = part.mass {
            r.range(&format!("{pp}.mass"), m, limits::MASS_KG, "kg");
        }
        if let Some(d) = part.density {
            r.range(&format!("{pp}.density"), d, limits::DENSITY_KG_M3, "kg/m³");
        }
        if body.kind == BodyKindDesc::Dynamic
            && body.mass.is_none()
            && body.density.is_none()
            && part.mass.is_none()
            && part.density.is_none()
        {
            r.add(
                &pp,
                "a part of a dynamic compound needs 'mass' or 'density' (or the body's 'mass' or 'density')",
            );
        }
        if let Some(m) = &part.material {
            if !materials.iter().any(|x| &x.name == m) {
                r.add(format!("{pp}.material"), format!("no material named '{m}'"));
            }
        }
    }
    ok
}

/// A joint's type, axes, motors, limits and armature (the bodies are checked by the caller).
fn validate_joint(r: &mut Report, p: &str, jd: &super::format::JointDesc) {
    const TYPES: &str = "revolute, prismatic, cylindrical, universal, ball, free, fixed";
    let t = jd.kind.as_str();
    let (needs_axis, driven) = match t {
        "revolute" | "prismatic" => (true, 1),
        "cylindrical" | "universal" => (true, 2),
        "ball" | "free" | "fixed" => (false, 0),
        other => {
            r.add(
                format!("{p}.type"),
                format!("unknown joint type '{other}' ({TYPES})"),
            );
            (false, 0)
        }
    };
    r.coords3(&format!("{p}.anchor"), &jd.anchor, limits::POSITION_M, "m");
    match &jd.axis {
        None if needs_axis => r.add(format!("{p}.axis"), format!("a {t} joint needs an axis")),
        Some(a) => r.direction(&format!("{p}.axis"), a),
        None => {}
    }
    match (&jd.axis2, t) {
        (None, "universal") => r.add(
            format!("{p}.axis2"),
            "a universal joint needs a second axis",
        ),
        (Some(a2), "universal") => {
            r.direction(&format!("{p}.axis2"), a2);
            if let Some(a1) = &jd.axis {
                let unit = |a: &[f64; 3]| {
                    let n = norm(a);
                    [a[0] / n, a[1] / n, a[2] / n]
                };
                let (u, w) = (unit(a1), unit(a2));
                let c = [
                    u[1] * w[2] - u[2] * w[1],
                    u[2] * w[0] - u[0] * w[2],
                    u[0] * w[1] - u[1] * w[0],
                ];
                let s = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
                if s.is_finite() && s < 1e-6 {
                    r.add(
                        format!("{p}.axis2"),
                        "must not be parallel to axis (a universal joint turns about two axes)",
                    );
                }
            }
        }
        (Some(_), _) => r.add(format!("{p}.axis2"), "only a universal joint takes axis2"),
        (None, _) => {}
    }
    let coordinate = |r: &mut Report, path: String, k: usize, seen: &mut [bool; 2]| -> bool {
        if k >= driven {
            let which = if driven == 0 {
                format!("a {t} joint has no driven coordinates (motors, limits and armature act on revolute, prismatic, cylindrical and universal joints)")
            } else {
                format!(
                    "a {t} joint has {driven} driven coordinate(s) (0 … {}), got {k}",
                    driven - 1
                )
            };
            r.add(path, which);
            return false;
        }
        if seen[k] {
            r.add(path, format!("coordinate {k} is given twice"));
            return false;
        }
        seen[k] = true;
        true
    };
    let q_range = (-limits::TREE_Q, limits::TREE_Q);
    let mut seen = [false; 2];
    for (i, m) in jd.motors.iter().enumerate() {
        let mp = format!("{p}.motors[{i}]");
        coordinate(r, format!("{mp}.coordinate"), m.coordinate, &mut seen);
        if let Some(x) = m.target_position {
            r.range(&format!("{mp}.target_position"), x, q_range, "");
        }
        r.range(
            &format!("{mp}.target_velocity"),
            m.target_velocity,
            q_range,
            "",
        );
        for (f, x) in [
            ("stiffness", m.stiffness),
            ("damping", m.damping),
            ("max_force", m.max_force),
        ] {
            r.non_negative(&format!("{mp}.{f}"), x, 1e9, "");
        }
    }
    let mut seen = [false; 2];
    for (i, l) in jd.limits.iter().enumerate() {
        let lp = format!("{p}.limits[{i}]");
        coordinate(r, format!("{lp}.coordinate"), l.coordinate, &mut seen);
        r.range(&format!("{lp}.lower"), l.lower, q_range, "");
        r.range(&format!("{lp}.upper"), l.upper, q_range, "");
        if l.lower.is_finite() && l.upper.is_finite() && l.upper < l.lower {
            r.add(
                format!("{lp}.upper"),
                format!(
                    "must be at least lower ({}), got {}",
                    num(l.lower),
                    num(l.upper)
                ),
            );
        }
        r.range(&format!("{lp}.restitution"), l.restitution, (0.0, 1.0), "");
    }
    if jd.armature.len() > driven {
        r.add(
            format!("{p}.armature"),
            format!(
                "a {t} joint has {driven} driven coordinate(s), got {} armature value(s)",
                jd.armature.len()
            ),
        );
    }
    for (k, &x) in jd.armature.iter().enumerate() {
        r.non_negative(&format!("{p}.armature[{k}]"), x, 1e9, "");
    }
}
