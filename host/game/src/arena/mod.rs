//! The table as a Virtual Physics world, stepped at 1 kHz (paper §5, §5.1).
//!
//! [`Arena`] builds the world from a [`Table`] ([`build`]: field, cover, walls with goal
//! mouths and goal boxes, corner ramps, the ball; [`rods`]: each rod an articulated tree —
//! a cylindrical joint from the table to the rod, its bar and men as the shapes of the rod's
//! link, the player's hand as a force- and torque-limited servo on each degree of freedom,
//! the travel's limits), maps the targets it is given to the servos' targets ([`drive`]:
//! rubber bumpers at the travel ends), takes one world step of [`DT_S`] and reports the
//! ball's state and its contacts ([`contacts`]) as the [`crate::rules`] want them.
//!
//! Table frame throughout (see [`crate::table`]): metres, `z` up, rods along `y`, a rod's
//! pose is its slide along `+y` and its angle about `+y` (0 = feet down); each man is
//! rigid on his rod, hinged at the shoulder on the rod axis, exactly as
//! `foosball_render::FrameSnapshot::posed` draws him.
//!
//! Everything that moves is the physics': a man pinning the ball stops his rod at the
//! hand's force while the target keeps going, a kick's speed comes from the foot's impact,
//! the ball's velocity is its body's. The ball: a dynamic sphere with the table's diameter
//! and mass, friction and spin from the contacts, rolling resistance on the cloth, the
//! table's (deliberately exaggerated) restitution against men and walls, and the world's
//! continuous collision (`tests/arena.rs`, `tests/computer_matches.rs` check every step).

pub mod build;
pub mod contacts;
pub mod drive;
pub mod parts;
pub mod rods;

pub use build::BodyRole;
pub use drive::RodDrive;
pub use parts::{ROD_RADIUS_M, WALL_THICKNESS_M};

use crate::ai::RodTarget;
use crate::rules::{BallState, Contact};
use crate::table::{Table, TableError};
use virtual_physics::algebra::Vec3;
use virtual_physics::pipeline::{BodyHandle, Effect, Effects, SolverSettings, TreeHandle, World};

/// The physics step, s: 1 ms (1 kHz), one world step.
pub const DT_S: f64 = 1e-3;

/// Standard gravity, m/s².
pub const GRAVITY_M_PER_S2: f64 = 9.81;

/// Why an arena could not be built.
#[derive(Debug, thiserror::Error)]
pub enum ArenaError {
    /// The table is not valid.
    #[error("invalid table: {0}")]
    Table(#[from] TableError),
    /// A setting is out of range.
    #[error("arena setting {what} must be {expected}, got {value}")]
    Setting {
        /// Which setting.
        what: &'static str,
        /// What it must be.
        expected: &'static str,
        /// What it is.
        value: f64,
    },
    /// A rod's shapes or mass gave no rigid body (a table the validation let through).
    #[error("rod {rod} cannot be built as an articulated body")]
    Rod {
        /// The rod's index in the table.
        rod: usize,
    },
}

/// Tunable physics of the arena (what the paper tuned for playability) and the player's
/// hand.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArenaSettings {
    /// Solver substeps of the one world step per millisecond.
    pub substeps: usize,
    /// Contact stiffness, Hz (capped by the engine at a quarter of the substep rate).
    pub contact_hertz: f64,
    /// Damping ratio of the soft contacts: lower pushes an overlap out faster (a pinned
    /// ball pressed at the hand's force overlaps the foot by less).
    pub contact_damping_ratio: f64,
    /// Approach speed below which contacts do not bounce, m/s.
    pub restitution_threshold_m_per_s: f64,
    /// Restitution of the ball on the cloth (walls and men use the table's ball
    /// restitution), 0…1.
    pub field_restitution: f64,
    /// Restitution inside the goal boxes (a goal should stay in), 0…1.
    pub goal_restitution: f64,
    /// Friction coefficient of the men (mixed with the ball's as `sqrt(μa μb)`).
    pub man_friction: f64,
    /// Rubber bumper length at each travel end, m: where the slide's target saturates.
    pub bumper_m: f64,
    /// Strongest push or pull of the hand along a rod, N.
    pub hand_force_n: f64,
    /// Strongest twist of the hand about a rod, N·m.
    pub hand_torque_n_m: f64,
    /// Natural frequency of the hand's servos on each rod's own mass and inertia, Hz.
    pub servo_hertz: f64,
    /// Damping ratio of the hand's servos.
    pub servo_damping_ratio: f64,
    /// Whether the table has its transparent cover at wall height.
    pub cover: bool,
    /// Fastest push-out of an overlap, m/s.
    pub max_push_velocity_m_per_s: f64,
}

impl Default for ArenaSettings {
    /// 4 substeps and 1 kHz contacts (a 27 g ball pressed by a rod at the hand's force
    /// overlaps it by well under a millimetre), bounces above 0.1 m/s, a lively but lower
    /// bounce on the cloth (0.3), 5 mm rubber bumpers, a strong player's hand (200 N along
    /// the rod, 15 N·m about it: the game README says where these come from) on 150 Hz
    /// critically damped servos, covered table.
    fn default() -> Self {
        Self {
            substeps: 4,
            contact_hertz: 1000.0,
            contact_damping_ratio: 1.0,
            restitution_threshold_m_per_s: 0.1,
            field_restitution: 0.3,
            goal_restitution: 0.1,
            man_friction: 0.6,
            bumper_m: 0.005,
            hand_force_n: 200.0,
            hand_torque_n_m: 15.0,
            servo_hertz: 150.0,
            servo_damping_ratio: 1.0,
            cover: true,
            max_push_velocity_m_per_s: 3.0,
        }
    }
}

impl ArenaSettings {
    fn validate(&self) -> Result<(), ArenaError> {
        let check = |what, value: f64, ok: bool, expected| {
            if ok && value.is_finite() {
                Ok(())
            } else {
                Err(ArenaError::Setting {
                    what,
                    expected,
                    value,
                })
            }
        };
        check(
            "substeps",
            self.substeps as f64,
            (1..=64).contains(&self.substeps),
            "1…64",
        )?;
        for (what, v) in [
            ("contact_hertz", self.contact_hertz),
            ("contact_damping_ratio", self.contact_damping_ratio),
            ("hand_force_n", self.hand_force_n),
            ("hand_torque_n_m", self.hand_torque_n_m),
            ("servo_hertz", self.servo_hertz),
            ("servo_damping_ratio", self.servo_damping_ratio),
            ("max_push_velocity_m_per_s", self.max_push_velocity_m_per_s),
        ] {
            check(what, v, v > 0.0, "positive")?;
        }
        check(
            "restitution_threshold_m_per_s",
            self.restitution_threshold_m_per_s,
            self.restitution_threshold_m_per_s >= 0.0,
            "≥ 0",
        )?;
        for (what, v) in [
            ("field_restitution", self.field_restitution),
            ("goal_restitution", self.goal_restitution),
        ] {
            check(what, v, (0.0..=1.0).contains(&v), "within 0…1")?;
        }
        check(
            "man_friction",
            self.man_friction,
            (0.0..=10.0).contains(&self.man_friction),
            "within 0…10",
        )?;
        check("bumper_m", self.bumper_m, self.bumper_m >= 0.0, "≥ 0")
    }
}

/// What one arena step produced.
#[derive(Debug, Clone, PartialEq)]
pub struct ArenaStep {
    /// The ball after the step.
    pub ball: BallState,
    /// The ball's contacts during the step (one per thing touched: field, walls, each rod).
    pub contacts: Vec<Contact>,
}

/// The table as a physics world. See the [module](self) docs. A clone is a snapshot that
/// steps on exactly as the arena would.
#[derive(Clone)]
pub struct Arena {
    table: Table,
    settings: ArenaSettings,
    world: World,
    /// Role of each body, by storage index.
    roles: Vec<BodyRole>,
    /// Each rod's tree.
    rods: Vec<TreeHandle>,
    /// Each rod's link body (bar and men).
    rod_bodies: Vec<BodyHandle>,
    drives: Vec<RodDrive>,
    ball: BodyHandle,
    /// The ball's storage index (as the manifolds name it).
    ball_index: usize,
    /// Every body's handle, by storage index (the order of `roles`).
    handles: Vec<BodyHandle>,
    /// Where each rod is asked to go.
    targets: Vec<RodTarget>,
    /// The servos' targets of the last step.
    motor_targets: Vec<RodTarget>,
    steps: u64,
    physics_errors: u64,
}

impl Arena {
    /// The arena of `table` with the default [`ArenaSettings`]: rods centred and upright,
    /// the ball at rest on the centre spot.
    pub fn new(table: &Table) -> Result<Arena, ArenaError> {
        Self::with_settings(table, ArenaSettings::default())
    }

    /// The arena of `table` with `settings`.
    pub fn with_settings(table: &Table, settings: ArenaSettings) -> Result<Arena, ArenaError> {
        table.validate()?;
        settings.validate()?;
        let effects = Effects::of(&[
            Effect::Gravity,
            Effect::Contacts,
            Effect::Friction,
            Effect::Restitution,
            Effect::RollingResistance,
            Effect::ContinuousCollision,
            Effect::Articulated,
        ]);
        let solver = SolverSettings {
            substeps: settings.substeps,
            contact_hertz: settings.contact_hertz,
            contact_damping_ratio: settings.contact_damping_ratio,
            restitution_threshold: settings.restitution_threshold_m_per_s,
            // The ball is small: 5 mm of speculative distance is plenty with the swept
            // margin of continuous collision on top.
            speculative_distance: 0.005,
            max_push_velocity: settings.max_push_velocity_m_per_s,
            ..SolverSettings::default()
        };
        let mut world = World::builder(effects)
            .dt(DT_S)
            .gravity(Vec3::new(0.0, 0.0, -GRAVITY_M_PER_S2))
            .settings(solver)
            .build();
        let built = build::build(table, &settings, &mut world)?;
        let handles: Vec<BodyHandle> = world.body_handles().collect();
        let ball_index = handles.iter().position(|&h| h == built.ball).unwrap_or(0);
        let drives = table
            .rods
            .iter()
            .map(|r| RodDrive {
                half_travel_m: r.half_travel_m(),
                bumper_m: settings.bumper_m,
            })
            .collect();
        let n = table.rods.len();
        Ok(Arena {
            table: table.clone(),
            settings,
            world,
            roles: built.roles,
            rods: built.rods,
            rod_bodies: built.rod_bodies,
            drives,
            ball: built.ball,
            ball_index,
            handles,
            targets: vec![RodTarget::default(); n],
            motor_targets: vec![RodTarget::default(); n],
            steps: 0,
            physics_errors: 0,
        })
    }

    /// The table.
    pub fn table(&self) -> &Table {
        &self.table
    }

    /// The settings.
    pub fn settings(&self) -> &ArenaSettings {
        &self.settings
    }

    /// Where the rods should go (table frame, per rod of the table; missing entries keep
    /// their last target): the hand's servos pull them there within the hand's force and
    /// torque, the slide within the travel (rubber bumpers at the ends).
    pub fn set_rod_targets(&mut self, targets: &[RodTarget]) {
        for (t, new) in self.targets.iter_mut().zip(targets) {
            *t = *new;
        }
    }

    /// The current targets.
    pub fn rod_targets(&self) -> &[RodTarget] {
        &self.targets
    }

    /// One 1 ms step: the servos' targets from the rods' targets, then one world step.
    pub fn step(&mut self) -> ArenaStep {
        for (i, tree) in self.rods.iter().enumerate() {
            let last = self.motor_targets[i];
            let t = self.drives[i].motor_target(self.targets[i], last);
            let v = [
                (t.angle_rad - last.angle_rad) / DT_S,
                (t.slide_m - last.slide_m) / DT_S,
            ];
            self.motor_targets[i] = t;
            if let Some(sys) = self.world.tree_mut(*tree) {
                for (dof, q, qd) in [
                    (rods::SPIN, t.angle_rad, v[0]),
                    (rods::SLIDE, t.slide_m, v[1]),
                ] {
                    if let Some(m) = sys.motor_mut(dof) {
                        m.target_position = Some(q);
                        m.target_velocity = if qd.is_finite() { qd } else { 0.0 };
                    }
                }
            }
        }
        let before = self.ball_body_state();
        if self.world.step().is_err() {
            self.physics_errors += 1;
        }
        let contacts = contacts::ball_contacts(
            &self.world,
            &self.roles,
            &self.handles,
            self.ball,
            &before,
            self.table.ball.mass_kg,
        );
        self.steps += 1;
        ArenaStep {
            ball: self.ball(),
            contacts,
        }
    }

    /// The ball's position (m) and velocity (m/s), table frame.
    pub fn ball(&self) -> BallState {
        let (p, v) = self
            .world
            .body(self.ball)
            .map_or((Vec3::zeros(), Vec3::zeros()), |b| {
                (b.position(), b.linear_velocity())
            });
        BallState {
            position: [p.x, p.y, p.z],
            velocity: [v.x, v.y, v.z],
        }
    }

    /// The ball's angular velocity (spin), rad/s, table frame.
    pub fn ball_spin(&self) -> [f64; 3] {
        let w = self
            .world
            .body(self.ball)
            .map_or(Vec3::zeros(), |b| b.angular_velocity());
        [w.x, w.y, w.z]
    }

    /// Where the rods are in physics: each rod's slide (m) and angle (rad).
    pub fn rod_poses(&self) -> Vec<RodTarget> {
        self.rods
            .iter()
            .map(|t| {
                self.world
                    .tree(*t)
                    .map_or(RodTarget::default(), |s| RodTarget {
                        slide_m: s.q()[rods::SLIDE],
                        angle_rad: s.q()[rods::SPIN],
                    })
            })
            .collect()
    }

    /// Each rod's velocity: `[slide m/s, spin rad/s]`.
    pub fn rod_velocities(&self) -> Vec<[f64; 2]> {
        self.rods
            .iter()
            .map(|t| {
                self.world
                    .tree(*t)
                    .map_or([0.0; 2], |s| [s.qd()[rods::SLIDE], s.qd()[rods::SPIN]])
            })
            .collect()
    }

    /// The mean force (N) along rod `rod` and torque (N·m) about it that its hand's servos
    /// and travel limits gave over the last step, `[slide, spin]`.
    pub fn rod_drive_forces(&self, rod: usize) -> [f64; 2] {
        self.rods
            .get(rod)
            .and_then(|t| self.world.tree(*t))
            .map_or([0.0; 2], |s| {
                [
                    s.drive_force(rods::SLIDE, DT_S),
                    s.drive_force(rods::SPIN, DT_S),
                ]
            })
    }

    /// The body of rod `rod`'s link (its bar and men), in [`Arena::world`].
    pub fn rod_body(&self, rod: usize) -> Option<BodyHandle> {
        self.rod_bodies.get(rod).copied()
    }

    /// The ball's body, in [`Arena::world`].
    pub fn ball_body(&self) -> BodyHandle {
        self.ball
    }

    /// Puts the ball at `position` (m) with `velocity` (m/s) and no spin.
    pub fn place_ball(&mut self, position: [f64; 3], velocity: [f64; 3]) {
        if let Some(mut b) = self.world.body_mut(self.ball) {
            b.set_position(Vec3::from(position))
                .set_linear_velocity(Vec3::from(velocity))
                .set_angular_velocity(Vec3::zeros());
        }
    }

    /// Puts the ball's spin (rad/s, table frame).
    pub fn set_ball_spin(&mut self, spin: [f64; 3]) {
        if let Some(mut b) = self.world.body_mut(self.ball) {
            b.set_angular_velocity(Vec3::from(spin));
        }
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Steps whose physics reported an error (none expected; counted, not fatal).
    pub fn physics_errors(&self) -> u64 {
        self.physics_errors
    }

    /// The physics world (read only: for measurements and checks).
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The role of every body of the world, by storage index (as
    /// [`World::body_handles`] lists them).
    pub fn roles(&self) -> &[BodyRole] {
        &self.roles
    }

    /// The gap (m) between the ball and the nearest solid (wall, ramp, goal box, man,
    /// rod, field, cover) and what that is: negative when the ball overlaps it. Computed
    /// from the shapes, independently of the engine's contacts (for tunnelling checks).
    pub fn ball_clearance(&self) -> (f64, BodyRole) {
        let [x, y, z] = self.ball().position;
        self.clearance_at([x, y, z])
    }

    /// The gap (m) a ball centred at `point` would have to the nearest solid, and what
    /// that is (the same as [`Arena::ball_clearance`] for another centre).
    pub fn clearance_at(&self, point: [f64; 3]) -> (f64, BodyRole) {
        contacts::clearance(
            &self.world,
            &self.roles,
            self.ball_index,
            self.table.ball.radius_m(),
            &Vec3::from(point),
        )
    }

    /// Whether the ball's centre is inside the table: over the field between the walls
    /// and under the cover, or inside a goal box (each with `tolerance_m` of slack).
    pub fn ball_in_bounds(&self, tolerance_m: f64) -> bool {
        let [x, y, z] = self.ball().position;
        let f = &self.table.field;
        let g = &self.table.goal;
        let tol = tolerance_m;
        let (hl, hw) = (0.5 * f.length_m, 0.5 * f.width_m);
        let on_field = x.abs() <= hl + tol && y.abs() <= hw + tol;
        let in_goal = x.abs() <= hl + g.depth_m + tol
            && y.abs() <= 0.5 * g.width_m + tol
            && z <= g.height_m + tol;
        let top = if self.settings.cover {
            build::cover_height_m(&self.table)
        } else {
            f64::INFINITY
        };
        z >= -tol && z <= top + tol && (on_field || in_goal)
    }

    fn ball_body_state(&self) -> contacts::BallBefore {
        let b = self.world.body(self.ball);
        contacts::BallBefore {
            position: b.map_or(Vec3::zeros(), |b| b.position()),
            velocity: b.map_or(Vec3::zeros(), |b| b.linear_velocity()),
            spin: b.map_or(Vec3::zeros(), |b| b.angular_velocity()),
        }
    }
}
