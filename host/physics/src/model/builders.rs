//! The reference models shared with the peer scripts (Pinocchio fixtures and timings):
//! serial chains, a humanoid-like branched tree, and a tree with 1:10⁴ mass ratios.
//! Every number is rounded to a few decimals (or is an exact rotation entry) so the JSON is
//! short and both sides read the same values. Deterministic: a fixed-seed generator.

use rand_core::{RngCore, SeedableRng};
use rand_xoshiro::SplitMix64;

use super::description::{
    BodyDescription, InertiaDescription, JointDescription, ModelDescription, PlacementDescription,
};

/// Gravity of every reference model (m/s², world frame).
pub(crate) const GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// The builders' fixed-seed generator: `rand_xoshiro`'s SplitMix64, as the game's and the
/// emulator's generators are.
struct Rng(SplitMix64);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(SplitMix64::seed_from_u64(seed))
    }

    /// Uniform in `[0, 1)`, from the top 53 bits.
    fn next(&mut self) -> f64 {
        (self.0.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in `[a, b]`, rounded to 1e-4.
    fn range(&mut self, a: f64, b: f64) -> f64 {
        ((a + (b - a) * self.next()) * 1e4).round() / 1e4
    }
}

const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn rot_x(angle: f64) -> [[f64; 3]; 3] {
    let (s, c) = crate::transcendental::sin_cos(angle);
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}

fn rot_z(angle: f64) -> [[f64; 3]; 3] {
    let (s, c) = crate::transcendental::sin_cos(angle);
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

/// Random but physically valid mass properties: mass scaled by `mass_scale`, centre of mass
/// near `(0, 0, length/2)`, principal moments within the triangle inequality, small products.
fn inertia(rng: &mut Rng, mass_scale: f64, length: f64) -> InertiaDescription {
    let m = rng.range(0.5, 2.0);
    let d = [
        rng.range(0.02, 0.035),
        rng.range(0.02, 0.035),
        rng.range(0.02, 0.035),
    ];
    let o = [
        rng.range(-0.002, 0.002),
        rng.range(-0.002, 0.002),
        rng.range(-0.002, 0.002),
    ];
    InertiaDescription {
        mass: m * mass_scale,
        com: [
            rng.range(-0.02, 0.02),
            rng.range(-0.02, 0.02),
            length / 2.0 + rng.range(-0.02, 0.02),
        ],
        inertia_com: [
            d[0] * mass_scale,
            d[1] * mass_scale,
            d[2] * mass_scale,
            o[0] * mass_scale,
            o[1] * mass_scale,
            o[2] * mass_scale,
        ],
    }
}

fn axis_joint(kind: &str, axis: [f64; 3]) -> JointDescription {
    JointDescription::with_axis(kind, axis)
}

const X: [f64; 3] = [1.0, 0.0, 0.0];
const Y: [f64; 3] = [0.0, 1.0, 0.0];
const Z: [f64; 3] = [0.0, 0.0, 1.0];

/// A serial chain of `n` revolute links whose axes alternate x, y, z; links 0.25 m long.
pub fn chain(n: usize) -> ModelDescription {
    let mut rng = Rng::new(0x5eed_0000 + n as u64);
    let bodies = (0..n)
        .map(|k| BodyDescription {
            name: format!("link{k}"),
            parent: k.checked_sub(1),
            joint: axis_joint("revolute", [X, Y, Z][k % 3]),
            placement: PlacementDescription {
                rotation: IDENTITY,
                translation: [0.0, 0.0, if k == 0 { 0.0 } else { 0.25 }],
            },
            inertia: inertia(&mut rng, 1.0, 0.25),
        })
        .collect();
    ModelDescription {
        name: format!("chain{n}"),
        gravity: GRAVITY,
        bodies,
    }
}

struct TreeBuilder {
    rng: Rng,
    bodies: Vec<BodyDescription>,
}

impl TreeBuilder {
    fn add(
        &mut self,
        name: &str,
        parent: Option<usize>,
        joint: JointDescription,
        rotation: [[f64; 3]; 3],
        translation: [f64; 3],
        mass_scale: f64,
    ) -> usize {
        let inertia = inertia(&mut self.rng, mass_scale, 0.2);
        self.bodies.push(BodyDescription {
            name: name.to_string(),
            parent,
            joint,
            placement: PlacementDescription {
                rotation,
                translation,
            },
            inertia,
        });
        self.bodies.len() - 1
    }
}

/// A humanoid-like floating tree, 27 bodies: free pelvis; waist, chest, neck, head; two arms
/// (ball shoulder, revolute roll and elbow, prismatic forearm, ball wrist, revolute hand);
/// two legs (ball hip, revolute knee, ankle pitch and roll, toe). Some joint frames are
/// rotated relative to their parents.
pub fn humanoid() -> ModelDescription {
    let mut t = TreeBuilder {
        rng: Rng::new(0x4855_4d41),
        bodies: Vec::new(),
    };
    let rev = |a| axis_joint("revolute", a);
    let ball = || JointDescription::new("ball");
    let pelvis = t.add(
        "pelvis",
        None,
        JointDescription::new("free"),
        IDENTITY,
        [0.0; 3],
        1.0,
    );
    let waist = t.add(
        "waist",
        Some(pelvis),
        rev(Z),
        IDENTITY,
        [0.0, 0.0, 0.1],
        1.0,
    );
    let chest = t.add(
        "chest",
        Some(waist),
        ball(),
        rot_z(0.3),
        [0.0, 0.0, 0.2],
        1.0,
    );
    let neck = t.add("neck", Some(chest), rev(Y), IDENTITY, [0.0, 0.0, 0.25], 1.0);
    t.add("head", Some(neck), ball(), IDENTITY, [0.0, 0.0, 0.08], 1.0);
    for (side, sign) in [("left", 1.0), ("right", -1.0)] {
        let shoulder = t.add(
            &format!("{side}_shoulder"),
            Some(chest),
            ball(),
            rot_x(sign * 0.5),
            [0.0, sign * 0.2, 0.2],
            1.0,
        );
        let upper = t.add(
            &format!("{side}_upper_arm"),
            Some(shoulder),
            rev(X),
            IDENTITY,
            [0.0, 0.0, -0.05],
            1.0,
        );
        let elbow = t.add(
            &format!("{side}_elbow"),
            Some(upper),
            rev([0.0, 0.6, 0.8]),
            IDENTITY,
            [0.0, 0.0, -0.25],
            1.0,
        );
        let forearm = t.add(
            &format!("{side}_forearm"),
            Some(elbow),
            axis_joint("prismatic", Z),
            IDENTITY,
            [0.0, 0.0, -0.1],
            1.0,
        );
        let wrist = t.add(
            &format!("{side}_wrist"),
            Some(forearm),
            ball(),
            rot_z(sign * 0.7),
            [0.0, 0.0, -0.15],
            1.0,
        );
        t.add(
            &format!("{side}_hand"),
            Some(wrist),
            rev(Y),
            IDENTITY,
            [0.0, 0.0, -0.05],
            1.0,
        );
    }
    for (side, sign) in [("left", 1.0), ("right", -1.0)] {
        let hip = t.add(
            &format!("{side}_hip"),
            Some(pelvis),
            ball(),
            rot_z(sign * 0.2),
            [0.0, sign * 0.1, -0.05],
            1.0,
        );
        let knee = t.add(
            &format!("{side}_knee"),
            Some(hip),
            rev(Y),
            IDENTITY,
            [0.0, 0.0, -0.4],
            1.0,
        );
        let ankle = t.add(
            &format!("{side}_ankle_pitch"),
            Some(knee),
            rev(Y),
            IDENTITY,
            [0.0, 0.0, -0.4],
            1.0,
        );
        let roll = t.add(
            &format!("{side}_ankle_roll"),
            Some(ankle),
            rev(X),
            IDENTITY,
            [0.0, 0.0, -0.02],
            1.0,
        );
        t.add(
            &format!("{side}_toe"),
            Some(roll),
            rev([0.0, 1.0, 0.0]),
            rot_x(0.1),
            [0.12, 0.0, -0.05],
            1.0,
        );
    }
    ModelDescription {
        name: "humanoid".to_string(),
        gravity: GRAVITY,
        bodies: t.bodies,
    }
}

/// A fixed-base tree of 12 bodies whose masses and inertias alternate between scales
/// 10⁻² and 10² (a 1:10⁴ ratio between neighbours), with revolute, prismatic and ball joints.
pub fn mass_ratio() -> ModelDescription {
    let mut t = TreeBuilder {
        rng: Rng::new(0x4d41_5353),
        bodies: Vec::new(),
    };
    let scale = |k: usize| if k % 2 == 0 { 1e2 } else { 1e-2 };
    let joints = [
        axis_joint("revolute", Z),
        axis_joint("revolute", X),
        JointDescription::new("ball"),
        axis_joint("prismatic", Y),
        axis_joint("revolute", Y),
        axis_joint("revolute", [0.0, 0.6, 0.8]),
    ];
    let mut parent = None;
    let mut trunk = Vec::new();
    for (k, joint) in joints.iter().enumerate() {
        let id = t.add(
            &format!("trunk{k}"),
            parent,
            joint.clone(),
            if k % 2 == 1 { rot_z(0.4) } else { IDENTITY },
            [0.0, 0.0, if k == 0 { 0.0 } else { 0.2 }],
            scale(k),
        );
        trunk.push(id);
        parent = Some(id);
    }
    let mut parent = Some(trunk[2]);
    for k in 6..12 {
        let id = t.add(
            &format!("branch{k}"),
            parent,
            joints[(k + 3) % 6].clone(),
            IDENTITY,
            [0.15, 0.0, 0.05],
            scale(k + 1),
        );
        parent = Some(id);
    }
    ModelDescription {
        name: "mass_ratio".to_string(),
        gravity: GRAVITY,
        bodies: t.bodies,
    }
}

/// The models compared against Pinocchio: chains of 7, 30, 100 links, the humanoid, the
/// mass-ratio tree.
pub fn peer_models() -> Vec<ModelDescription> {
    vec![chain(7), chain(30), chain(100), humanoid(), mass_ratio()]
}

/// A random state `(q, q̇, τ)` for `tree` (deterministic in `seed`), drawn like the peer
/// script draws them: revolute angles in (−π, π), prismatic offsets in (−0.2, 0.2) m, ball and
/// free rotations of up to 3 rad, free translations in (−1, 1) m, velocities ~ ±1, forces ~ ±5.
pub fn random_state(
    tree: &super::ArticulatedTree<f64>,
    seed: u64,
) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = Rng::new(seed);
    let mut u = |a: f64, b: f64| a + (b - a) * rng.next();
    let mut q = Vec::with_capacity(tree.nq());
    for b in tree.bodies() {
        match b.joint.type_name() {
            "revolute" => q.push(u(-core::f64::consts::PI, core::f64::consts::PI)),
            "prismatic" => q.push(u(-0.2, 0.2)),
            "ball" | "free" => {
                let d = [u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)];
                let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-3);
                let angle = u(0.0, 3.0);
                q.extend(d.iter().map(|x| x / n * angle));
                if b.joint.type_name() == "free" {
                    q.extend([u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0)]);
                }
            }
            _ => q.extend((0..b.nq()).map(|_| u(-1.0, 1.0))),
        }
    }
    let qd = (0..tree.nv()).map(|_| u(-1.0, 1.0)).collect();
    let tau = (0..tree.nv()).map(|_| u(-5.0, 5.0)).collect();
    (q, qd, tau)
}
