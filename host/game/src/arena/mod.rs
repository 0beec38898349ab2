//! The table as a Virtual Physics world, stepped at 1 kHz (paper §5, §5.1).
//!
//! [`Arena`] builds the world from a [`Table`] ([`build`]: field, cover, walls with goal
//! mouths and goal boxes, corner ramps, rods, men, ball), drives the rods towards the
//! targets it is given ([`drive`]: kinematic bodies with the velocity that reaches the
//! target, rubber bumpers at the travel ends), steps the world by [`DT_S`] and reports
//! the ball's state and its contacts ([`contacts`]) as the [`crate::rules`] want them.
//!
//! Table frame throughout (see [`crate::table`]): metres, `z` up, rods along `y`, a rod's
//! pose is its slide along `+y` and its angle about `+y` (0 = feet down); each man is
//! rigid on his rod, hinged at the shoulder on the rod axis, exactly as
//! `foosball_render::FrameSnapshot::posed` draws him.
//!
//! The ball: a dynamic sphere with the table's diameter and mass, friction and spin from
//! the contacts, rolling resistance on the cloth, the table's (deliberately exaggerated)
//! restitution against men and walls, and continuous collision (speculative contacts
//! swept by the velocity), so it does not tunnel through men or walls
//! (`tests/arena.rs`, `tests/computer_matches.rs` check every step).

pub mod build;
pub mod contacts;
pub mod drive;

pub use build::{BodyRole, ROD_RADIUS_M, WALL_THICKNESS_M};
pub use drive::RodDrive;

use crate::ai::RodTarget;
use crate::rules::{BallState, Contact, ContactWith};
use crate::table::{Table, TableError};
use build::RodBodies;
use virtual_physics::dynamics::BodyKind;
use virtual_physics::geometry::V3;
use virtual_physics::pipeline::{Effect, Effects, SolverSettings, World};

/// The physics step, s: 1 ms (1 kHz).
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
}

/// Tunable physics of the arena (what the paper tuned for playability).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArenaSettings {
    /// Most physics world steps per 1 ms arena step (collision detection runs once per
    /// world step). More than one keeps the engine's speculative contacts honest at
    /// speed: a speculative contact closes along the normal found at the start of a
    /// world step, so a fast ball passing a corner (a goal post, a man's edge) within
    /// about one world step's travel of it can be stopped or bounced as if it had
    /// touched (`tests/arena.rs::a_fast_ball_enters_the_goal_beside_the_post`). Each step
    /// uses as few as keep the travel per world step within `world_step_travel_m`.
    pub world_steps: usize,
    /// Longest travel of the ball (or of a foot near it) per world step, m.
    pub world_step_travel_m: f64,
    /// Solver substeps per world step.
    pub substeps: usize,
    /// Contact stiffness, Hz (capped by the engine at a quarter of the substep rate).
    pub contact_hertz: f64,
    /// Approach speed below which contacts do not bounce, m/s.
    pub restitution_threshold_m_per_s: f64,
    /// Restitution of the ball on the cloth (walls and men use the table's ball
    /// restitution), 0…1.
    pub field_restitution: f64,
    /// Restitution inside the goal boxes (a goal should stay in), 0…1.
    pub goal_restitution: f64,
    /// Friction coefficient of the men (mixed with the ball's as `sqrt(μa μb)`).
    pub man_friction: f64,
    /// Rubber bumper length at each travel end, m.
    pub bumper_m: f64,
    /// Fastest rod slide, m/s.
    pub max_slide_speed_m_per_s: f64,
    /// Fastest rod spin, rad/s.
    pub max_spin_rad_per_s: f64,
    /// Whether the table has its transparent cover at wall height.
    pub cover: bool,
    /// A rod whose men end a step deeper than this in the ball is held where it was for
    /// that step (the ball pins it), m.
    pub pin_overlap_m: f64,
    /// Fastest push-out of an overlap, m/s: above a foot's speed (reach · spin), so a
    /// foot coming down on the ball squeezes it out instead of pinning it into the cloth.
    pub max_push_velocity_m_per_s: f64,
    /// Fastest the ball may move, m/s: faster is scaled down after the step (a guard
    /// for playability and for continuous collision; hard shots reach ~15 m/s).
    pub max_ball_speed_m_per_s: f64,
}

impl Default for ArenaSettings {
    /// 1 to 4 world steps (at most 5 mm of travel each) with 1 substep each (a lone
    /// ball needs no stacking stiffness; the cost is measured by
    /// `space-foosball bench match`), 250 Hz contacts, bounces above 0.1 m/s, a lively
    /// but lower bounce on the cloth (0.3), 5 mm rubber bumpers, rods up to 5 m/s and
    /// 200 rad/s (about twice a strong player), covered table, ball at most 20 m/s.
    fn default() -> Self {
        Self {
            world_steps: 4,
            world_step_travel_m: 0.005,
            substeps: 1,
            contact_hertz: 250.0,
            restitution_threshold_m_per_s: 0.1,
            field_restitution: 0.3,
            goal_restitution: 0.1,
            man_friction: 0.6,
            bumper_m: 0.005,
            max_slide_speed_m_per_s: 5.0,
            max_spin_rad_per_s: 200.0,
            cover: true,
            max_ball_speed_m_per_s: 20.0,
            max_push_velocity_m_per_s: 10.0,
            pin_overlap_m: 0.002,
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
            "world_steps",
            self.world_steps as f64,
            (1..=64).contains(&self.world_steps),
            "1…64",
        )?;
        check(
            "substeps",
            self.substeps as f64,
            (1..=64).contains(&self.substeps),
            "1…64",
        )?;
        check(
            "contact_hertz",
            self.contact_hertz,
            self.contact_hertz > 0.0,
            "positive",
        )?;
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
        check("bumper_m", self.bumper_m, self.bumper_m >= 0.0, "≥ 0")?;
        check(
            "world_step_travel_m",
            self.world_step_travel_m,
            self.world_step_travel_m > 0.0,
            "positive",
        )?;
        check(
            "pin_overlap_m",
            self.pin_overlap_m,
            self.pin_overlap_m >= 0.0,
            "≥ 0",
        )?;
        check(
            "max_push_velocity_m_per_s",
            self.max_push_velocity_m_per_s,
            self.max_push_velocity_m_per_s > 0.0,
            "positive",
        )?;
        check(
            "max_ball_speed_m_per_s",
            self.max_ball_speed_m_per_s,
            self.max_ball_speed_m_per_s > 0.0,
            "positive",
        )?;
        check(
            "max_slide_speed_m_per_s",
            self.max_slide_speed_m_per_s,
            self.max_slide_speed_m_per_s > 0.0,
            "positive",
        )?;
        check(
            "max_spin_rad_per_s",
            self.max_spin_rad_per_s,
            self.max_spin_rad_per_s > 0.0,
            "positive",
        )
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

/// The table as a physics world. See the [module](self) docs.
pub struct Arena {
    table: Table,
    settings: ArenaSettings,
    world: World,
    roles: Vec<BodyRole>,
    rods: Vec<RodBodies>,
    drives: Vec<RodDrive>,
    ball: usize,
    /// Where each rod is (pose reached at the end of the last step).
    poses: Vec<RodTarget>,
    /// Where each rod is asked to go.
    targets: Vec<RodTarget>,
    /// Each rod's velocity over the last step: slide m/s, spin rad/s.
    rod_velocities: Vec<[f64; 2]>,
    steps: u64,
    physics_errors: u64,
    pinned_steps: u64,
    /// The ball's displacement over the last step / the step, m/s.
    ball_velocity: V3,
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
        let built = build::build(table, &settings);
        let effects = Effects::of(&[
            Effect::Gravity,
            Effect::Contacts,
            Effect::Friction,
            Effect::Restitution,
            Effect::RollingResistance,
            Effect::ContinuousCollision,
        ]);
        let solver = SolverSettings {
            substeps: settings.substeps,
            contact_hertz: settings.contact_hertz,
            restitution_threshold: settings.restitution_threshold_m_per_s,
            // The ball is small: 5 mm of speculative distance is plenty with the swept
            // margin of continuous collision on top.
            speculative_distance: 0.005,
            max_push_velocity: settings.max_push_velocity_m_per_s,
            ..SolverSettings::default()
        };
        let world = World::new(
            built.bodies,
            effects,
            DT_S / settings.world_steps as f64,
            V3::new(0.0, 0.0, -GRAVITY_M_PER_S2),
            solver,
        );
        let drives = table
            .rods
            .iter()
            .map(|r| RodDrive {
                half_travel_m: r.half_travel_m(),
                bumper_m: settings.bumper_m,
                max_slide_speed_m_per_s: settings.max_slide_speed_m_per_s,
                max_spin_rad_per_s: settings.max_spin_rad_per_s,
            })
            .collect();
        let n = table.rods.len();
        let mut arena = Arena {
            table: table.clone(),
            settings,
            world,
            roles: built.roles,
            rods: built.rods,
            drives,
            ball: built.ball,
            poses: vec![RodTarget::default(); n],
            targets: vec![RodTarget::default(); n],
            rod_velocities: vec![[0.0; 2]; n],
            steps: 0,
            physics_errors: 0,
            pinned_steps: 0,
            ball_velocity: V3::zeros(),
        };
        arena.pose_rod_bodies();
        Ok(arena)
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
    /// their last target). The rods get there at the speed limits, the slide within the
    /// travel (rubber bumpers at the ends).
    pub fn set_rod_targets(&mut self, targets: &[RodTarget]) {
        for (t, new) in self.targets.iter_mut().zip(targets) {
            *t = *new;
        }
    }

    /// The current targets.
    pub fn rod_targets(&self) -> &[RodTarget] {
        &self.targets
    }

    /// One 1 ms step: rods towards their targets, the ball by the physics.
    pub fn step(&mut self) -> ArenaStep {
        // Rod velocities that reach this step's poses.
        let mut next = Vec::with_capacity(self.poses.len());
        for i in 0..self.poses.len() {
            let (pose, v) = self.drives[i].next(self.poses[i], self.targets[i], DT_S);
            next.push(pose);
            self.rod_velocities[i] = v;
        }
        // Bodies exactly at the current poses, moving with those velocities.
        self.pose_rod_bodies();
        let mut contacts = Vec::new();
        let start = self.world.bodies.pos[self.ball];
        let world_steps = self.world_steps_now();
        self.world.dt = DT_S / world_steps as f64;
        for _ in 0..world_steps {
            let before = self.ball_body_state();
            if self.world.step().is_err() {
                self.physics_errors += 1;
            }
            let v = &mut self.world.bodies.vel[self.ball];
            let speed = v.norm();
            if speed > self.settings.max_ball_speed_m_per_s {
                *v *= self.settings.max_ball_speed_m_per_s / speed;
            }
            contacts::merge(
                &mut contacts,
                contacts::ball_contacts(&self.world, &self.roles, self.ball, &before),
            );
        }
        // A rod whose men ended the step deep in the ball, or that touched the ball
        // while it ended the step deep in the cloth, a wall or another man, was stopped
        // by it (a pinned ball cannot give way): it stays where it was, as a real rod
        // stops on a pinned ball.
        let ball_at = self.world.bodies.pos[self.ball];
        let squeezed = contacts
            .iter()
            .any(|c| matches!(c.with, ContactWith::Man { .. }))
            && -self.ball_clearance().0 > self.settings.pin_overlap_m;
        for (i, pose) in next.iter_mut().enumerate() {
            let touched = squeezed
                && contacts
                    .iter()
                    .any(|c| c.with == ContactWith::Man { rod: i });
            if touched || self.rod_overlap(i, &ball_at) > self.settings.pin_overlap_m {
                *pose = self.poses[i];
                self.rod_velocities[i] = [0.0; 2];
                self.pinned_steps += 1;
            }
        }
        self.ball_velocity = (self.world.bodies.pos[self.ball] - start) / DT_S;
        self.poses = next;
        // The bodies where the rods are now (held rods back where they were).
        self.pose_rod_bodies();
        self.steps += 1;
        ArenaStep {
            ball: self.ball(),
            contacts,
        }
    }

    /// The ball's position and velocity, table frame. The velocity is the ball's
    /// displacement over the last step divided by the step (what the ball did, m/s),
    /// not the solver's body velocity, which in a squeeze (the ball pinned between a
    /// moving man and the cloth) can be metres per second while the ball stays put.
    pub fn ball(&self) -> BallState {
        let (p, v) = (self.world.bodies.pos[self.ball], self.ball_velocity);
        BallState {
            position: [p.x, p.y, p.z],
            velocity: [v.x, v.y, v.z],
        }
    }

    /// The ball's angular velocity (spin), rad/s, table frame.
    pub fn ball_spin(&self) -> [f64; 3] {
        let w = self.world.bodies.omega[self.ball];
        [w.x, w.y, w.z]
    }

    /// Where the rods are in physics (the poses reached by the last step).
    pub fn rod_poses(&self) -> Vec<RodTarget> {
        self.poses.clone()
    }

    /// Each rod's velocity over the last step: `[slide m/s, spin rad/s]`.
    pub fn rod_velocities(&self) -> &[[f64; 2]] {
        &self.rod_velocities
    }

    /// Puts the ball at `position` (m) with `velocity` (m/s) and no spin.
    pub fn place_ball(&mut self, position: [f64; 3], velocity: [f64; 3]) {
        let b = &mut self.world.bodies;
        b.pos[self.ball] = V3::from(position);
        b.vel[self.ball] = V3::from(velocity);
        b.omega[self.ball] = V3::zeros();
        b.awake[self.ball] = true;
        self.ball_velocity = V3::from(velocity);
    }

    /// Puts the ball's spin (rad/s, table frame).
    pub fn set_ball_spin(&mut self, spin: [f64; 3]) {
        self.world.bodies.omega[self.ball] = V3::from(spin);
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

    /// The role of every body of the world, by index.
    pub fn roles(&self) -> &[BodyRole] {
        &self.roles
    }

    /// The gap (m) between the ball and the nearest solid (wall, ramp, goal box, man,
    /// rod, field, cover) and what that is: negative when the ball overlaps it. Computed
    /// from the shapes, independently of the engine's contacts (for tunnelling checks).
    pub fn ball_clearance(&self) -> (f64, BodyRole) {
        let c = self.world.bodies.pos[self.ball];
        contacts::clearance(&self.world, &self.roles, self.ball, &c)
    }

    /// The gap (m) a ball centred at `point` would have to the nearest solid, and what
    /// that is (the same as [`Arena::ball_clearance`] for another centre).
    pub fn clearance_at(&self, point: [f64; 3]) -> (f64, BodyRole) {
        contacts::clearance(&self.world, &self.roles, self.ball, &V3::from(point))
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

    /// World steps for this 1 ms step: enough that neither the ball nor the feet of
    /// the rods near it move more than [`ArenaSettings::world_step_travel_m`] per world
    /// step, at most [`ArenaSettings::world_steps`].
    fn world_steps_now(&self) -> usize {
        let b = &self.world.bodies;
        let ball = b.pos[self.ball];
        let mut speed = b.vel[self.ball].norm();
        for (i, rod) in self.rods.iter().enumerate() {
            let reach = self.table.character_of(i).foot_reach_m;
            if (ball.x - rod.x_m).abs() < reach + 0.05 {
                let [vs, w] = self.rod_velocities[i];
                speed = speed.max(vs.abs() + w.abs() * reach);
            }
        }
        let wanted = (speed * DT_S / self.settings.world_step_travel_m).ceil();
        if wanted.is_finite() {
            (wanted as usize).clamp(1, self.settings.world_steps)
        } else {
            self.settings.world_steps
        }
    }

    /// How deep (m) a ball centred at `centre` is inside the men or the bar of rod
    /// `rod` (0 when clear).
    fn rod_overlap(&self, rod: usize, centre: &V3) -> f64 {
        let bodies = &self.rods[rod];
        let reach = self.table.character_of(rod).foot_reach_m + self.table.ball.radius_m() + 0.03;
        if (centre.x - bodies.x_m).abs() > reach {
            return 0.0;
        }
        let r = self.table.ball.radius_m();
        std::iter::once(bodies.bar)
            .chain(bodies.parts.iter().map(|p| p.body))
            .filter_map(|b| contacts::signed_distance(&self.world, b, centre))
            .map(|d| r - d)
            .fold(0.0, f64::max)
    }

    /// Steps in which a rod was held back by a pinned ball (counted per rod).
    pub fn pinned_steps(&self) -> u64 {
        self.pinned_steps
    }

    /// Places every rod's bar and men exactly at the current poses, moving with the
    /// rods' current velocities.
    fn pose_rod_bodies(&mut self) {
        let rod_h = self.table.field.rod_height_m;
        let b = &mut self.world.bodies;
        for (i, rod) in self.rods.iter().enumerate() {
            let pose = self.poses[i];
            let [vs, w] = self.rod_velocities[i];
            let rot = build::rot_y(pose.angle_rad);
            let omega = V3::new(0.0, w, 0.0);
            let slide_v = V3::new(0.0, vs, 0.0);
            debug_assert_eq!(b.kind[rod.bar], BodyKind::Kinematic);
            b.pos[rod.bar] = V3::new(rod.x_m, pose.slide_m, rod_h);
            b.rot[rod.bar] = rot * build::z_to_y_rotation();
            b.vel[rod.bar] = slide_v;
            b.omega[rod.bar] = omega;
            for part in &rod.parts {
                let pivot = V3::new(rod.x_m, part.offset_m + pose.slide_m, rod_h);
                let arm = rot * part.local_centre;
                b.pos[part.body] = pivot + arm;
                b.rot[part.body] = rot * part.local_rot;
                b.vel[part.body] = slide_v + omega.cross(&arm);
                b.omega[part.body] = omega;
            }
        }
    }

    fn ball_body_state(&self) -> contacts::BallBefore {
        let b = &self.world.bodies;
        contacts::BallBefore {
            position: b.pos[self.ball],
            velocity: b.vel[self.ball],
            spin: b.omega[self.ball],
        }
    }
}
