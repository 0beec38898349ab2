//! The table → the bodies and trees of a Virtual Physics world.
//!
//! Everything here is in the table frame (see [`crate::table`]): metres, `z` up, the
//! field surface at `z = 0`. Bodies:
//!
//! * **field**: a fixed half-space `z ≤ 0` (the cloth: rolling resistance, low bounce);
//! * **cover**: a fixed half-space at [`cover_height_m`] (above the men's sweep), the
//!   table's transparent lid, so a lifted ball falls back instead of leaving the table;
//! * **walls**: fixed boxes up to the cover — two side walls with a slot where each rod
//!   passes through, two end walls each split around its goal mouth (two pieces beside
//!   it, a lintel above it), and per goal a box behind the mouth (two sides, back, roof)
//!   whose floor is the field;
//! * **corner ramps**: in each corner a fixed box whose top face is the plane rising from
//!   the field to `corner_ramp_height_m` at the corner over `corner_ramp_m` along both
//!   walls (below the field elsewhere, so it only shows in the corner);
//! * **rods**: one articulated tree each ([`super::rods`]): the bar and its men are the
//!   shapes of one link on a cylindrical joint;
//! * **ball**: a dynamic sphere.

use super::parts::{ROD_RADIUS_M, WALL_THICKNESS_M};
use super::rods;
use super::{ArenaError, ArenaSettings};
use crate::table::Table;
use virtual_physics::algebra::{Mat3, Vec3};
use virtual_physics::geometry::{Material, Shape};
use virtual_physics::pipeline::{BodyBuilder, BodyHandle, TreeHandle, World};

/// Gap around a rod where it passes through a side wall, m: more than the speculative
/// contact distance, so a bar spinning in its slot does not touch the wall.
pub(crate) const ROD_SLOT_GAP_M: f64 = 0.008;
/// Half thickness of the corner-ramp boxes, m.
const RAMP_HALF_THICKNESS_M: f64 = 0.05;

/// What a body of the arena is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BodyRole {
    /// The playing surface.
    Field,
    /// A wall, the cover, a corner ramp or a goal box.
    Wall,
    /// The link of rod `rod`: its steel bar and all its men (one compound body).
    Man(usize),
    /// The ball.
    Ball,
}

/// The built world's bodies and trees.
pub(crate) struct Built {
    /// Role of each body of the world, by storage index.
    pub(crate) roles: Vec<BodyRole>,
    /// Each rod's tree, per rod of the table.
    pub(crate) rods: Vec<TreeHandle>,
    /// Each rod's link body (bar and men), per rod of the table.
    pub(crate) rod_bodies: Vec<BodyHandle>,
    /// The ball.
    pub(crate) ball: BodyHandle,
}

/// The materials of the arena, from the table's ball and the settings.
pub(crate) struct Materials {
    cloth: Material,
    wall: Material,
    goal: Material,
    /// The men and the bars.
    pub(crate) man: Material,
    ball: Material,
}

impl Materials {
    /// Friction mixes as `sqrt(μa μb)`, restitution and rolling resistance as the larger
    /// of the two: so the ball carries the friction and no bounce, and each surface its
    /// own bounce (walls and men the table's exaggerated restitution, the cloth less).
    pub(crate) fn new(table: &Table, settings: &ArenaSettings) -> Self {
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

struct Builder<'w> {
    world: &'w mut World,
    roles: Vec<(BodyHandle, BodyRole)>,
}

impl Builder<'_> {
    fn fixed(&mut self, shape: Shape, centre: Vec3, rot: Mat3, material: Material, role: BodyRole) {
        let h = self.world.insert_body(
            BodyBuilder::fixed(shape)
                .name(format!("{role:?}"))
                .material(material)
                .position(centre)
                .rotation(rot),
        );
        self.roles.push((h, role));
    }

    fn fixed_box(&mut self, centre: Vec3, half: Vec3, rot: Mat3, material: Material) {
        self.fixed(
            Shape::Cuboid { half },
            centre,
            rot,
            material,
            BodyRole::Wall,
        );
    }

    /// An axis-aligned fixed box from its corners (nothing when it is empty).
    fn wall(&mut self, min: Vec3, max: Vec3, material: Material) {
        if (max - min).min() > 0.0 {
            self.fixed_box(
                (min + max) * 0.5,
                (max - min) * 0.5,
                Mat3::identity(),
                material,
            );
        }
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
/// The two corner ramps at end `sx` (−1: Home's end, +1: Away's) of a field of half
/// length `hl` and half width `hw` (m): fixed boxes whose top faces are the planes rising
/// from the field to the ramp's height at the corner.
fn corner_ramps(
    b: &mut Builder<'_>,
    f: &crate::table::Field,
    sx: f64,
    hl: f64,
    hw: f64,
    m: &Materials,
) {
    if f.corner_ramp_m > 0.0 && f.corner_ramp_height_m > 0.0 {
        for sy in [-1.0f64, 1.0] {
            let (r, h) = (f.corner_ramp_m, f.corner_ramp_height_m);
            let n = Vec3::new(-sx * h / r, -sy * h / r, 1.0).normalize();
            let x_axis = Vec3::new(sx, -sy, 0.0).normalize();
            let y_axis = n.cross(&x_axis);
            let rot = Mat3::from_columns(&[x_axis, y_axis, n]);
            // A point of the ramp plane above the centroid of its corner triangle.
            let on_plane = Vec3::new(sx * (hl - r / 3.0), sy * (hw - r / 3.0), h / 3.0);
            let centre = on_plane - n * RAMP_HALF_THICKNESS_M;
            b.fixed_box(
                centre,
                Vec3::new(1.5 * r, 1.5 * r, RAMP_HALF_THICKNESS_M),
                rot,
                m.wall,
            );
        }
    }
}

/// Builds the table into the empty `world`: fixed geometry, one tree per rod (centred,
/// feet down), the ball at rest in the middle.
pub(crate) fn build(
    table: &Table,
    settings: &ArenaSettings,
    world: &mut World,
) -> Result<Built, ArenaError> {
    let m = Materials::new(table, settings);
    let f = &table.field;
    let g = &table.goal;
    let t = WALL_THICKNESS_M;
    let (hl, hw) = (0.5 * f.length_m, 0.5 * f.width_m);
    // The walls reach up to the cover.
    let wh = cover_height_m(table);
    let (gw, gh, gd) = (0.5 * g.width_m, g.height_m, g.depth_m);
    let mut b = Builder {
        world,
        roles: Vec::new(),
    };
    b.fixed(
        Shape::HalfSpace { normal: Vec3::z() },
        Vec3::zeros(),
        Mat3::identity(),
        m.cloth,
        BodyRole::Field,
    );
    if settings.cover {
        b.fixed(
            Shape::HalfSpace { normal: -Vec3::z() },
            Vec3::new(0.0, 0.0, wh),
            Mat3::identity(),
            m.wall,
            BodyRole::Wall,
        );
    }
    // Side walls, over the whole length and the end walls' thickness, with a slot where
    // each rod passes through: below the slots, above them, and between them.
    let slot = ROD_RADIUS_M + ROD_SLOT_GAP_M;
    let (z0, z1) = (f.rod_height_m - slot, f.rod_height_m + slot);
    let mut xs: Vec<f64> = table.rods.iter().map(|r| r.x_m).collect();
    xs.sort_by(f64::total_cmp);
    for sy in [-1.0, 1.0] {
        let (y0, y1) = if sy > 0.0 {
            (hw, hw + t)
        } else {
            (-hw - t, -hw)
        };
        b.wall(
            Vec3::new(-hl - t, y0, -t),
            Vec3::new(hl + t, y1, z0),
            m.wall,
        );
        b.wall(
            Vec3::new(-hl - t, y0, z1),
            Vec3::new(hl + t, y1, wh),
            m.wall,
        );
        let mut from = -hl - t;
        for &x in &xs {
            b.wall(Vec3::new(from, y0, z0), Vec3::new(x - slot, y1, z1), m.wall);
            from = x + slot;
        }
        b.wall(Vec3::new(from, y0, z0), Vec3::new(hl + t, y1, z1), m.wall);
    }
    for sx in [-1.0f64, 1.0] {
        let (x0, x1) = if sx > 0.0 {
            (hl, hl + t)
        } else {
            (-hl - t, -hl)
        };
        // End wall beside the mouth, both sides.
        b.wall(Vec3::new(x0, gw, -t), Vec3::new(x1, hw + t, wh), m.wall);
        b.wall(Vec3::new(x0, -hw - t, -t), Vec3::new(x1, -gw, wh), m.wall);
        // Lintel above the mouth.
        b.wall(Vec3::new(x0, -gw, gh), Vec3::new(x1, gw, wh), m.wall);
        // The goal box behind the mouth: sides, back, roof (floor: the field).
        let (gx0, gx1) = if sx > 0.0 {
            (hl, hl + gd + t)
        } else {
            (-hl - gd - t, -hl)
        };
        b.wall(
            Vec3::new(gx0, gw, -t),
            Vec3::new(gx1, gw + t, gh + t),
            m.goal,
        );
        b.wall(
            Vec3::new(gx0, -gw - t, -t),
            Vec3::new(gx1, -gw, gh + t),
            m.goal,
        );
        let (bx0, bx1) = if sx > 0.0 {
            (hl + gd, hl + gd + t)
        } else {
            (-hl - gd - t, -hl - gd)
        };
        b.wall(
            Vec3::new(bx0, -gw - t, -t),
            Vec3::new(bx1, gw + t, gh + t),
            m.goal,
        );
        b.wall(
            Vec3::new(gx0, -gw - t, gh),
            Vec3::new(gx1, gw + t, gh + t),
            m.goal,
        );
        corner_ramps(&mut b, f, sx, hl, hw, &m);
    }
    let r = table.ball.radius_m();
    let ball = b.world.insert_body(
        BodyBuilder::dynamic(Shape::Sphere { radius: r })
            .name("ball")
            .material(m.ball)
            .mass(table.ball.mass_kg)
            .position(Vec3::new(0.0, 0.0, r)),
    );
    b.roles.push((ball, BodyRole::Ball));
    // Rods and men: one tree per rod.
    let mut trees = Vec::with_capacity(table.rods.len());
    let mut rod_bodies = Vec::with_capacity(table.rods.len());
    for i in 0..table.rods.len() {
        let system = rods::rod_system(table, i, settings, m.man)?;
        let tree = b.world.insert_tree(system);
        let body = b
            .world
            .link_body(tree.link(0))
            .ok_or(ArenaError::Rod { rod: i })?;
        trees.push(tree);
        rod_bodies.push(body);
    }
    // Roles by storage index; a rod's link is named through the world's link map.
    let world = &*b.world;
    let roles = world
        .body_handles()
        .map(|h| {
            if let Some(link) = world.link_of(h) {
                let rod = trees.iter().position(|t| *t == link.tree);
                return rod.map_or(BodyRole::Wall, BodyRole::Man);
            }
            b.roles
                .iter()
                .find(|(k, _)| *k == h)
                .map_or(BodyRole::Wall, |(_, role)| *role)
        })
        .collect();
    Ok(Built {
        roles,
        rods: trees,
        rod_bodies,
        ball,
    })
}
