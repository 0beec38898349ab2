//! The table → the bodies of a Virtual Physics world.
//!
//! Everything here is in the table frame (see [`crate::table`]): metres, `z` up, the
//! field surface at `z = 0`. Bodies:
//!
//! * **field**: a fixed half-space `z ≤ 0` (the cloth: rolling resistance, low bounce);
//! * **cover**: a fixed half-space at [`cover_height_m`] (above the men's sweep), the
//!   table's transparent lid, so a lifted ball falls back instead of leaving the table;
//! * **walls**: fixed boxes up to the cover — two side walls, two end walls each split around its goal
//!   mouth (two pieces beside it, a lintel above it), and per goal a box behind the mouth
//!   (two sides, back, roof) whose floor is the field;
//! * **corner ramps**: in each corner a fixed box whose top face is the plane rising from
//!   the field to `corner_ramp_height_m` at the corner over `corner_ramp_m` along both
//!   walls (below the field elsewhere, so it only shows in the corner);
//! * **rods**: kinematic cylinders along `y` at `rod_height_m`;
//! * **men**: per man the character's boxes ([`crate::table::CharacterParams::boxes`])
//!   with a rounded sole ([`man_shapes`]), each a kinematic body placed from the rod
//!   pose (hinged at the shoulder = the rod axis, rigid on the rod);
//! * **ball**: a dynamic sphere.

use super::ArenaSettings;
use crate::table::Table;
use virtual_physics::dynamics::{BodyKind, BodySet, Material};
use virtual_physics::geometry::{Shape, M3, V3};

/// Wall thickness, m: thick against tunnelling (the ball moves at most ~2 cm per step).
pub const WALL_THICKNESS_M: f64 = 0.05;
/// Radius of the steel rods, m (16 mm rods).
pub const ROD_RADIUS_M: f64 = 0.008;
/// How far the rods stick out through the side walls, m.
const ROD_OVERHANG_M: f64 = 0.1;
/// Half thickness of the corner-ramp boxes, m.
const RAMP_HALF_THICKNESS_M: f64 = 0.05;

/// What a body of the arena is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyRole {
    /// The playing surface.
    Field,
    /// A wall, the cover, a corner ramp or a goal box.
    Wall,
    /// The steel bar of rod `rod`.
    Rod(usize),
    /// A box of a man of rod `rod`.
    Man(usize),
    /// The ball.
    Ball,
}

/// One box of one man: where it sits on its rod.
#[derive(Debug, Clone, Copy)]
pub struct ManPart {
    /// Body index.
    pub body: usize,
    /// Offset of the man along the rod at slide 0, m.
    pub offset_m: f64,
    /// Shape centre in the man frame (origin on the rod axis at the man's centre), m.
    pub local_centre: V3,
    /// Shape orientation in the man frame.
    pub local_rot: M3,
}

/// The bodies of one rod.
#[derive(Debug, Clone)]
pub struct RodBodies {
    /// The bar (kinematic cylinder).
    pub bar: usize,
    /// Every box of every man on it.
    pub parts: Vec<ManPart>,
    /// Rod axis position along `x`, m.
    pub x_m: f64,
}

/// The built bodies and what each one is.
pub struct Built {
    /// The bodies, for `World::new`.
    pub bodies: BodySet,
    /// Role of each body, by index.
    pub roles: Vec<BodyRole>,
    /// Per rod of the table.
    pub rods: Vec<RodBodies>,
    /// The ball's index.
    pub ball: usize,
}

/// Rotation about `+y` by `angle` (rad): the rod's turn (0 = feet down).
pub fn rot_y(angle: f64) -> M3 {
    let (s, c) = angle.sin_cos();
    M3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

/// Rotation taking the body `z` axis to the table's `+y` (cylinders lie along body `z`).
pub fn z_to_y_rotation() -> M3 {
    M3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0)
}

/// The materials of the arena, from the table's ball and the settings.
struct Materials {
    cloth: Material,
    wall: Material,
    goal: Material,
    man: Material,
    ball: Material,
}

impl Materials {
    /// Friction mixes as `sqrt(μa μb)`, restitution and rolling resistance as the larger
    /// of the two: so the ball carries the friction and no bounce, and each surface its
    /// own bounce (walls and men the table's exaggerated restitution, the cloth less).
    fn new(table: &Table, settings: &ArenaSettings) -> Self {
        let b = &table.ball;
        let mu = b.friction;
        Self {
            cloth: Material {
                friction: mu,
                restitution: settings.field_restitution,
                // Engine: torque = coefficient · radius · N; table: torque = lever · N.
                rolling_resistance: b.rolling_resistance_m / b.radius_m(),
            },
            wall: Material {
                friction: mu,
                restitution: b.restitution,
                rolling_resistance: 0.0,
            },
            goal: Material {
                friction: mu,
                restitution: settings.goal_restitution,
                rolling_resistance: 0.0,
            },
            man: Material {
                friction: settings.man_friction,
                restitution: b.restitution,
                rolling_resistance: 0.0,
            },
            ball: Material {
                friction: mu,
                restitution: 0.0,
                rolling_resistance: 0.0,
            },
        }
    }
}

struct Builder {
    bodies: BodySet,
    roles: Vec<BodyRole>,
}

impl Builder {
    fn fixed_box(&mut self, centre: V3, half: V3, rot: M3, material: Material) -> usize {
        self.push(
            BodyRole::Wall,
            BodyKind::Fixed,
            Shape::Cuboid { half },
            material,
            0.0,
            centre,
            rot,
        )
    }

    /// An axis-aligned fixed box from its corners.
    fn wall(&mut self, min: V3, max: V3, material: Material) -> usize {
        self.fixed_box(
            (min + max) * 0.5,
            (max - min) * 0.5,
            M3::identity(),
            material,
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn push(
        &mut self,
        role: BodyRole,
        kind: BodyKind,
        shape: Shape,
        material: Material,
        mass: f64,
        pos: V3,
        rot: M3,
    ) -> usize {
        self.roles.push(role);
        self.bodies.push(
            format!("{role:?}"),
            kind,
            shape,
            material,
            mass,
            pos,
            rot,
            V3::zeros(),
            V3::zeros(),
        )
    }
}

/// Height of the table's cover (and of the walls in the physics), m: the table's wall
/// height, or higher so that a ball fits between the cover and the highest point any
/// man sweeps when his rod turns (the rod height plus the longer of foot reach and head
/// height) — a lower cover would trap the ball against spinning men.
pub fn cover_height_m(table: &Table) -> f64 {
    let sweep = table
        .teams
        .iter()
        .map(|t| {
            let p = t.character_params();
            p.foot_reach_m.max(p.head_height_m)
        })
        .fold(0.0, f64::max);
    table
        .field
        .wall_height_m
        .max(table.field.rod_height_m + sweep + table.ball.diameter_m + 0.01)
}

/// The physical shapes of one man, man frame: `(shape, centre, orientation)`.
///
/// The character's two boxes ([`crate::table::CharacterParams::boxes`]: body, leg),
/// except that the leg's sole is rounded: the leg box stops `r` above the sole and a
/// capsule of radius `r = body_depth / 2` lying along the rod (`y`, as wide as the
/// foot) makes the sole, its bottom exactly at the foot reach. A foot that comes down
/// on the ball then squeezes it out sideways (the contact normal points from the
/// rounded sole to the ball's centre) instead of pressing it flat into the cloth, which
/// a flat kinematic sole does. The drawn men (square soles) differ only in the two
/// sole edges, by at most `r (1 − 1/√2)` ≈ 2 mm.
pub fn man_shapes(character: &crate::table::CharacterParams) -> Vec<(Shape, V3, M3)> {
    let [body, leg] = character.boxes();
    let r = 0.5 * character.body_depth_m;
    let sole_centre_z = -character.foot_reach_m + r;
    let leg_top = leg.centre[2] + leg.half_extents[2];
    let leg_half_z = 0.5 * (leg_top - sole_centre_z);
    vec![
        (
            Shape::Cuboid {
                half: V3::from(body.half_extents),
            },
            V3::from(body.centre),
            M3::identity(),
        ),
        (
            Shape::Cuboid {
                half: V3::new(leg.half_extents[0], leg.half_extents[1], leg_half_z),
            },
            V3::new(leg.centre[0], leg.centre[1], sole_centre_z + leg_half_z),
            M3::identity(),
        ),
        (
            Shape::Capsule {
                radius: r,
                half_height: (leg.half_extents[1] - r).max(0.0),
            },
            V3::new(leg.centre[0], leg.centre[1], sole_centre_z),
            z_to_y_rotation(),
        ),
    ]
}

/// Builds the bodies of `table` (rods at slide 0, angle 0; the ball at rest in the middle).
pub fn build(table: &Table, settings: &ArenaSettings) -> Built {
    let m = Materials::new(table, settings);
    let f = &table.field;
    let g = &table.goal;
    let t = WALL_THICKNESS_M;
    let (hl, hw) = (0.5 * f.length_m, 0.5 * f.width_m);
    // The walls reach up to the cover.
    let wh = cover_height_m(table);
    let (gw, gh, gd) = (0.5 * g.width_m, g.height_m, g.depth_m);
    let mut b = Builder {
        bodies: BodySet::default(),
        roles: Vec::new(),
    };
    b.push(
        BodyRole::Field,
        BodyKind::Fixed,
        Shape::HalfSpace { normal: V3::z() },
        m.cloth,
        0.0,
        V3::zeros(),
        M3::identity(),
    );
    if settings.cover {
        b.push(
            BodyRole::Wall,
            BodyKind::Fixed,
            Shape::HalfSpace { normal: -V3::z() },
            m.wall,
            0.0,
            V3::new(0.0, 0.0, wh),
            M3::identity(),
        );
    }
    // Side walls, over the whole length and the end walls' thickness.
    for sy in [-1.0, 1.0] {
        let (y0, y1) = if sy > 0.0 {
            (hw, hw + t)
        } else {
            (-hw - t, -hw)
        };
        b.wall(V3::new(-hl - t, y0, -t), V3::new(hl + t, y1, wh), m.wall);
    }
    for sx in [-1.0f64, 1.0] {
        let (x0, x1) = if sx > 0.0 {
            (hl, hl + t)
        } else {
            (-hl - t, -hl)
        };
        // End wall beside the mouth, both sides.
        b.wall(V3::new(x0, gw, -t), V3::new(x1, hw + t, wh), m.wall);
        b.wall(V3::new(x0, -hw - t, -t), V3::new(x1, -gw, wh), m.wall);
        // Lintel above the mouth.
        b.wall(V3::new(x0, -gw, gh), V3::new(x1, gw, wh), m.wall);
        // The goal box behind the mouth: sides, back, roof (floor: the field).
        let (gx0, gx1) = if sx > 0.0 {
            (hl, hl + gd + t)
        } else {
            (-hl - gd - t, -hl)
        };
        b.wall(V3::new(gx0, gw, -t), V3::new(gx1, gw + t, gh + t), m.goal);
        b.wall(V3::new(gx0, -gw - t, -t), V3::new(gx1, -gw, gh + t), m.goal);
        let (bx0, bx1) = if sx > 0.0 {
            (hl + gd, hl + gd + t)
        } else {
            (-hl - gd - t, -hl - gd)
        };
        b.wall(
            V3::new(bx0, -gw - t, -t),
            V3::new(bx1, gw + t, gh + t),
            m.goal,
        );
        b.wall(
            V3::new(gx0, -gw - t, gh),
            V3::new(gx1, gw + t, gh + t),
            m.goal,
        );
        // Corner ramps.
        if f.corner_ramp_m > 0.0 && f.corner_ramp_height_m > 0.0 {
            for sy in [-1.0f64, 1.0] {
                let (r, h) = (f.corner_ramp_m, f.corner_ramp_height_m);
                let n = V3::new(-sx * h / r, -sy * h / r, 1.0).normalize();
                let x_axis = V3::new(sx, -sy, 0.0).normalize();
                let y_axis = n.cross(&x_axis);
                let rot = M3::from_columns(&[x_axis, y_axis, n]);
                // A point of the ramp plane above the centroid of its corner triangle.
                let on_plane = V3::new(sx * (hl - r / 3.0), sy * (hw - r / 3.0), h / 3.0);
                let centre = on_plane - n * RAMP_HALF_THICKNESS_M;
                b.fixed_box(
                    centre,
                    V3::new(1.5 * r, 1.5 * r, RAMP_HALF_THICKNESS_M),
                    rot,
                    m.wall,
                );
            }
        }
    }
    // Rods and men.
    let mut rods = Vec::with_capacity(table.rods.len());
    for (i, rod) in table.rods.iter().enumerate() {
        let bar = b.push(
            BodyRole::Rod(i),
            BodyKind::Kinematic,
            Shape::Cylinder {
                radius: ROD_RADIUS_M,
                half_height: hw + t + ROD_OVERHANG_M,
            },
            m.man,
            0.0,
            V3::new(rod.x_m, 0.0, f.rod_height_m),
            z_to_y_rotation(),
        );
        let character = table.character_of(i);
        let mut parts = Vec::new();
        for offset_m in rod.man_offsets() {
            for (shape, local_centre, local_rot) in man_shapes(&character) {
                let body = b.push(
                    BodyRole::Man(i),
                    BodyKind::Kinematic,
                    shape,
                    m.man,
                    0.0,
                    V3::new(rod.x_m, offset_m, f.rod_height_m) + local_centre,
                    local_rot,
                );
                parts.push(ManPart {
                    body,
                    offset_m,
                    local_centre,
                    local_rot,
                });
            }
        }
        rods.push(RodBodies {
            bar,
            parts,
            x_m: rod.x_m,
        });
    }
    let r = table.ball.radius_m();
    let ball = b.push(
        BodyRole::Ball,
        BodyKind::Dynamic,
        Shape::Sphere { radius: r },
        m.ball,
        table.ball.mass_kg,
        V3::new(0.0, 0.0, r),
        M3::identity(),
    );
    Built {
        bodies: b.bodies,
        roles: b.roles,
        rods,
        ball,
    }
}
