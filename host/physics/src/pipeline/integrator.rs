//! Free-body integrators on the group `SO(3) × ℝ³` / `SE(3)`, selectable per scene
//! (`"integrator"` in the scene JSON, [`World::set_integrator`](super::World::set_integrator)).
//!
//! The world calls two stages per substep of `h` seconds, with the constraint solve between
//! them: [`FreeIntegrator::integrate_velocities`] (gravity, applied forces and torques, the
//! gyroscopic term `−ω × Iω` when declared, damping) and
//! [`FreeIntegrator::integrate_positions`]. A body without constraints therefore takes the
//! integrator's full step; the solver's impulses change the velocities between the stages and
//! each integrator carries that change into the pose (see each kind).
//!
//! | kind | velocity stage | pose stage | order (measured, `vphys accuracy`) |
//! |---|---|---|---|
//! | `explicit-euler` | `ω += h I⁻¹(τ − ω×Iω)` at the old state | `R ← R·exp(h ω_old)`, `p += h v_old` | 1 |
//! | `symplectic-euler` | same | `T ← T·Exp(h V_new)` | 1 |
//! | `rkmk4` | classical RK4 on `(θ, ω_b)` with `θ̇ = dexp⁻¹_θ(ω_b)` (Munthe-Kaas) | `R ← R·exp(θ)`, `p += h(v₀+v₁)/2` | 4 |
//! | `energy-momentum` | implicit midpoint on the body momentum `Π` (Newton) | `R ← R·cay(h ω_mid)` | 2, energy and momentum exact |
//! | `implicit-gyroscopic` (default) | one Newton step of `I(ω−ω₀) + h ω×Iω = 0` (Catto 2015, Bullet) | `T ← T·Exp(h V_new)` | 1, dissipative |
//!
//! *The default.* `implicit-gyroscopic` is semi-implicit Euler with the gyroscopic term taken
//! implicitly: without the `gyroscopic` effect, or for a body whose `ω × Iω` vanishes (a
//! sphere, a symmetric body spinning about its axis), it is the same step as
//! `symplectic-euler`. The explicit gyroscopic term of `symplectic-euler` feeds energy into a
//! body tumbling fast about its intermediate axis (at `hω` = 0.28 rad per substep the energy
//! grows 2.6 × within 0.25 s, then overflows); the Newton step cannot gain energy there, it
//! loses some (the price: a fast tumble about the intermediate axis slows down).
//!
//! *Energy-momentum.* With `Π = I ω_b` the torque-free body obeys `Π̇ = Π × ω_b`. The
//! implicit midpoint rule `Π₁ = Π₀ + h Π_m × I⁻¹Π_m`, `Π_m = (Π₀+Π₁)/2`, preserves every
//! quadratic invariant, so the energy `½ Π·I⁻¹Π` and `|Π|²` are conserved to the Newton
//! tolerance; the rotation update `R₁ = R₀ cay(h ω̂_m)` makes `R₁Π₁ = R₀Π₀` (because
//! `Π₀ = cay(h ω̂_m) Π₁` is the same equation rewritten), so the world angular momentum is
//! conserved too. An applied torque enters as a kick `Π += h Rᵀτ` before the midpoint step.
//!
//! Every integrator moves kinematic bodies by `T ← T·Exp(h V)` (exact for their constant
//! velocity) and re-orthonormalises the moving bodies' rotations every
//! [`ORTHONORMALIZE_PERIOD`] substeps (one Newton–Schulz step, [`orthonormalize`]) so they stay
//! orthonormal to rounding after millions of steps.

use serde::{Deserialize, Serialize};

use super::pose_lanes::{lie_group_euler_body, lie_group_euler_positions};
use crate::algebra::exp_so3;
use crate::dynamics::{BodyKind, BodySet};
use crate::geometry::{M3, V3};

/// The integrators a scene can select.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum IntegratorKind {
    /// Explicit (forward) Euler on the group: the pose advances with the velocity at the start
    /// of the step. First order; gains energy.
    ExplicitEuler,
    /// Semi-implicit (symplectic) Euler: velocity first, with the gyroscopic term explicit,
    /// then `T ← T·Exp(h V)` with the new velocity. First order.
    SymplecticEuler,
    /// Runge–Kutta–Munthe-Kaas of order 4 (classical RK4 tableau in the exponential chart).
    Rkmk4,
    /// Energy- and momentum-conserving Lie–Poisson midpoint scheme for free rigid bodies
    /// (implicit midpoint on the body momentum, Cayley rotation update). Second order.
    EnergyMomentum,
    /// Catto's implicit gyroscopic step (GDC 2015, Bullet's `computeGyroscopicImpulseImplicit_Body`):
    /// one Newton step on the body-frame Euler equation, then `T ← T·Exp(h V)` as
    /// semi-implicit Euler. First order, dissipates energy; the default.
    #[default]
    ImplicitGyroscopic,
}

impl IntegratorKind {
    /// Every kind, in report order.
    pub const ALL: [IntegratorKind; 5] = [
        IntegratorKind::ExplicitEuler,
        IntegratorKind::SymplecticEuler,
        IntegratorKind::Rkmk4,
        IntegratorKind::EnergyMomentum,
        IntegratorKind::ImplicitGyroscopic,
    ];

    /// The scene-file name (`explicit-euler`, …).
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::ExplicitEuler => "explicit-euler",
            IntegratorKind::SymplecticEuler => "symplectic-euler",
            IntegratorKind::Rkmk4 => "rkmk4",
            IntegratorKind::EnergyMomentum => "energy-momentum",
            IntegratorKind::ImplicitGyroscopic => "implicit-gyroscopic",
        }
    }

    /// The kind with this scene-file name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

impl std::fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// What acts on the free bodies during a substep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeForces {
    /// Gravity (m/s², world); zero without the `gravity` effect.
    pub(crate) gravity: V3,
    /// Whether the gyroscopic term `−ω × Iω` is part of the model (`gyroscopic` effect).
    pub(crate) gyroscopic: bool,
    /// Velocity factors `(linear, angular)` applied after the update (`damping` effect).
    pub(crate) damping: Option<(f64, f64)>,
}

/// A free-body integrator with its per-body scratch (what the velocity stage leaves for the
/// pose stage). Buffers grow with the body set and are reused: no allocation per step.
#[derive(Clone, Debug, Default)]
pub struct FreeIntegrator {
    /// The selected kind.
    pub(crate) kind: IntegratorKind,
    /// Free (unconstrained) change of the linear velocity over the substep (m/s, world).
    dv: Vec<V3>,
    /// Angular velocity the velocity stage left (rad/s, world): the solver's change is
    /// `ω − w_free`.
    w_free: Vec<V3>,
    /// The rotation at the end of the free substep, world from body (RKMK4, energy-momentum).
    rot_end: Vec<M3>,
    /// Rotation vector of the substep, world (rad), for the solver's separation update.
    theta: Vec<V3>,
    /// Energy-momentum: body momentum at the start (after the torque kick), `Π_m`, and
    /// whether the body's midpoint solve is still iterating.
    pi0: Vec<V3>,
    pi_mid: Vec<V3>,
    pending: Vec<bool>,
    /// Pose stages since the rotations were last re-orthonormalised: the step's substeps, and
    /// the extra substeps of islands (counted apart, so that each set of bodies gets its turn).
    since_orthonormalized: [u32; 2],
}

/// Every this many pose stages the rotations of the moving bodies get one Newton–Schulz step
/// ([`orthonormalize`]). Measured without it (tumbling box, 1 ms, 10⁶ steps): `|RᵀR − I|`
/// reaches 1.3e-12 with semi-implicit Euler and 2e-13 with the others; with it it stays at
/// rounding level. Amortised cost: one 3×3 product pair per body every 256 substeps.
pub(crate) const ORTHONORMALIZE_PERIOD: u32 = 256;

/// The energy-momentum midpoint solve stops when an update is below this fraction of `|Π|`
/// (the error left is smaller by the contraction factor, < 1e-3 up to 1/30 s).
pub(crate) const MIDPOINT_TOLERANCE: f64 = 1e-8;
/// At most this many chord-Newton iterations.
const MIDPOINT_MAX_ITERATIONS: usize = 20;

fn skew(a: &V3) -> M3 {
    M3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// One Newton–Schulz step towards the nearest rotation, `R ← R (3I − RᵀR)/2`: quadratic
/// convergence, so a rotation with error `ε` (in `RᵀR − I`) comes back with error `~ε²`.
#[inline]
pub(crate) fn orthonormalize(r: &M3) -> M3 {
    let e = r.tr_mul(r);
    r * (M3::identity() * 1.5 - e * 0.5)
}

/// The Cayley map `cay(a) = (I − â/2)⁻¹(I + â/2) = I + 4/(4 + |a|²)(â + â²/2)` (exactly
/// orthogonal; rotation by `2 atan(|a|/2)` about `a`).
#[inline]
pub(crate) fn cayley(a: &V3) -> M3 {
    // â² = a aᵀ − |a|² I, written out: 9 products instead of a 3×3 matrix product.
    let n2 = a.norm_squared();
    let k = 4.0 / (4.0 + n2);
    let hk = 0.5 * k;
    let (x, y, z) = (a.x, a.y, a.z);
    let (kx, ky, kz) = (k * x, k * y, k * z);
    let (xy, xz, yz) = (hk * x * y, hk * x * z, hk * y * z);
    let d = 1.0 - hk * n2;
    M3::new(
        d + hk * x * x,
        xy - kz,
        xz + ky,
        xy + kz,
        d + hk * y * y,
        yz - kx,
        xz - ky,
        yz + kx,
        d + hk * z * z,
    )
}

/// The inverse of the right Jacobian of `SO(3)`: `θ̇ = J_r⁻¹(θ) ω` when `R(t) = R₀ exp(θ(t))`
/// and `Ṙ = R ω̂` (body angular velocity `ω`):
/// `J_r⁻¹(θ) ω = ω + ½ θ×ω + c(|θ|) θ×(θ×ω)`, `c = 1/θ² − (1+cos θ)/(2θ sin θ)` (→ 1/12).
#[inline]
pub(crate) fn dexp_inv_right(theta: &V3, w: &V3) -> V3 {
    let t2 = theta.norm_squared();
    let c = if t2 < 1e-4 {
        1.0 / 12.0 + t2 * (1.0 / 720.0 + t2 / 30240.0)
    } else {
        let t = t2.sqrt();
        let (s, co) = crate::transcendental::sin_cos(t);
        1.0 / t2 - (1.0 + co) / (2.0 * t * s)
    };
    let tw = theta.cross(w);
    w + tw * 0.5 + theta.cross(&tw) * c
}

/// Body angular acceleration `I⁻¹(τ_b − ω×Iω)` (rad/s², body); principal inertia `i`.
#[inline]
fn euler_rhs(w: &V3, i: &V3, inv_i: &V3, tau_b: &V3, gyro: bool) -> V3 {
    let mut t = *tau_b;
    if gyro {
        t -= w.cross(&i.component_mul(w));
    }
    inv_i.component_mul(&t)
}

impl FreeIntegrator {
    /// An integrator of `kind`.
    pub(crate) fn new(kind: IntegratorKind) -> Self {
        Self {
            kind,
            ..Self::default()
        }
    }

    fn ensure(&mut self, n: usize) {
        if self.dv.len() != n {
            self.dv.resize(n, V3::zeros());
            self.w_free.resize(n, V3::zeros());
            self.rot_end.resize(n, M3::identity());
            self.theta.resize(n, V3::zeros());
            self.pi0.resize(n, V3::zeros());
            self.pi_mid.resize(n, V3::zeros());
            self.pending.resize(n, false);
        }
    }

    /// The velocity stage over `h` seconds: the awake dynamic bodies' `vel` and `omega`
    /// become the velocities the solver then corrects.
    pub(crate) fn integrate_velocities(&mut self, b: &mut BodySet, h: f64, f: &FreeForces) {
        match self.kind {
            IntegratorKind::SymplecticEuler => symplectic_velocities(b, h, f),
            IntegratorKind::ImplicitGyroscopic => implicit_gyroscopic_velocities(b, h, f),
            kind => {
                self.ensure(b.len());
                if kind == IntegratorKind::EnergyMomentum && f.gyroscopic {
                    self.solve_midpoints(b, h);
                }
                for i in 0..b.len() {
                    if b.awake[i] {
                        self.body_velocity(kind, b, i, h, f);
                    }
                }
            }
        }
    }

    /// The energy-momentum midpoint solve for every awake body, one iteration per pass over
    /// the bodies (independent work per pass, so the processor overlaps the bodies instead of
    /// waiting on one body's chain of dependent iterations): leaves `Π₀` in `pi0` and `Π_m`
    /// in `pi_mid`.
    fn solve_midpoints(&mut self, b: &BodySet, h: f64) {
        let tol2 = MIDPOINT_TOLERANCE * MIDPOINT_TOLERANCE;
        for i in 0..b.len() {
            if b.awake[i] {
                let r = &b.rot[i];
                let p0 =
                    b.inertia[i].component_mul(&r.tr_mul(&b.omega[i])) + r.tr_mul(&b.torque[i]) * h;
                self.pi0[i] = p0;
                self.pi_mid[i] = midpoint_predictor(&p0, &b.inv_inertia[i], h);
                self.pending[i] = true;
            } else {
                self.pending[i] = false;
            }
        }
        for _ in 0..MIDPOINT_MAX_ITERATIONS {
            let mut any = false;
            for i in 0..b.len() {
                if self.pending[i] {
                    let p0 = self.pi0[i];
                    let d2 = midpoint_iteration(&mut self.pi_mid[i], &p0, &b.inv_inertia[i], h);
                    let done = d2 <= tol2 * p0.norm_squared();
                    self.pending[i] = !done;
                    any |= !done;
                }
            }
            if !any {
                break;
            }
        }
    }

    fn body_velocity(
        &mut self,
        kind: IntegratorKind,
        b: &mut BodySet,
        i: usize,
        h: f64,
        f: &FreeForces,
    ) {
        let v0 = b.vel[i];
        let mut v1 = v0 + (f.gravity + b.force[i] * b.inv_mass[i]) * h;
        let r = b.rot[i];
        let (inertia, inv_i) = (b.inertia[i], b.inv_inertia[i]);
        let wb0 = r.tr_mul(&b.omega[i]);
        let tau_b = r.tr_mul(&b.torque[i]);
        let gyro = f.gyroscopic;
        let mut w1 = match kind {
            IntegratorKind::ExplicitEuler => {
                let wb1 = wb0 + euler_rhs(&wb0, &inertia, &inv_i, &tau_b, gyro) * h;
                r * wb1
            }
            IntegratorKind::Rkmk4 => {
                let torque = b.torque[i] != V3::zeros();
                let tau_at = |theta: &V3| {
                    if torque {
                        (r * exp_so3(theta)).tr_mul(&b.torque[i])
                    } else {
                        tau_b
                    }
                };
                let acc = |theta: &V3, w: &V3| euler_rhs(w, &inertia, &inv_i, &tau_at(theta), gyro);
                let z = V3::zeros();
                let (kt1, kw1) = (wb0, acc(&z, &wb0));
                let (t2, w2) = (kt1 * (0.5 * h), wb0 + kw1 * (0.5 * h));
                let (kt2, kw2) = (dexp_inv_right(&t2, &w2), acc(&t2, &w2));
                let (t3, w3) = (kt2 * (0.5 * h), wb0 + kw2 * (0.5 * h));
                let (kt3, kw3) = (dexp_inv_right(&t3, &w3), acc(&t3, &w3));
                let (t4, w4) = (kt3 * h, wb0 + kw3 * h);
                let (kt4, kw4) = (dexp_inv_right(&t4, &w4), acc(&t4, &w4));
                let theta = (kt1 + (kt2 + kt3) * 2.0 + kt4) * (h / 6.0);
                let wb1 = wb0 + (kw1 + (kw2 + kw3) * 2.0 + kw4) * (h / 6.0);
                let r1 = r * exp_so3(&theta);
                self.rot_end[i] = r1;
                r1 * wb1
            }
            IntegratorKind::EnergyMomentum => {
                if gyro {
                    let (p0, x) = (self.pi0[i], self.pi_mid[i]);
                    let (p1, wm) = (x * 2.0 - p0, inv_i.component_mul(&x));
                    let r1 = r * cayley(&(wm * h));
                    self.rot_end[i] = r1;
                    r1 * inv_i.component_mul(&p1)
                } else {
                    let wb = inv_i.component_mul(&(inertia.component_mul(&wb0) + tau_b * h));
                    self.rot_end[i] = r * exp_so3(&(wb * h));
                    r * wb
                }
            }
            IntegratorKind::SymplecticEuler | IntegratorKind::ImplicitGyroscopic => {
                unreachable!("handled by symplectic_velocities and implicit_gyroscopic_velocities")
            }
        };
        if let Some((ld, ad)) = f.damping {
            v1 *= ld;
            w1 *= ad;
        }
        self.dv[i] = v1 - v0;
        // Linearised world rotation of the substep (for the solver's separation update).
        self.theta[i] = (b.omega[i] + w1) * (0.5 * h);
        self.w_free[i] = w1;
        if kind == IntegratorKind::ExplicitEuler {
            // The pose uses the old angular velocity plus the solver's change (ω − w_free).
            self.w_free[i] = w1 - b.omega[i];
        }
        b.vel[i] = v1;
        b.omega[i] = w1;
    }

    /// The pose stage over `h` seconds, after the solve; adds the change to `dp` and `dtheta`.
    pub(crate) fn integrate_positions(&mut self, b: &mut BodySet, h: f64) {
        self.positions(b, h, true);
    }

    /// The pose stage of an island's extra substep (`pipeline/island_substeps.rs`): the awake
    /// dynamic bodies alone (the island's, by their `awake` flags); the kinematic bodies took
    /// the step's substeps already.
    pub(crate) fn integrate_island_positions(&mut self, b: &mut BodySet, h: f64) {
        self.positions(b, h, false);
    }

    /// The pose stage, the kinematic bodies with it when `step` (the step's own substeps).
    fn positions(&mut self, b: &mut BodySet, h: f64, step: bool) {
        self.pose_stage(b, h, step);
        let since = &mut self.since_orthonormalized[usize::from(!step)];
        *since += 1;
        if *since >= ORTHONORMALIZE_PERIOD {
            *since = 0;
            for i in 0..b.len() {
                let moving = match b.kind[i] {
                    BodyKind::Dynamic => b.awake[i],
                    BodyKind::Kinematic => step && b.omega[i] != V3::zeros() && !b.is_link_proxy(i),
                    BodyKind::Fixed => false,
                };
                if moving {
                    b.rot[i] = orthonormalize(&b.rot[i]);
                }
            }
        }
    }

    fn pose_stage(&mut self, b: &mut BodySet, h: f64, kinematic: bool) {
        match self.kind {
            IntegratorKind::SymplecticEuler | IntegratorKind::ImplicitGyroscopic => {
                lie_group_euler_positions(b, h, kinematic)
            }
            kind => {
                for i in 0..b.len() {
                    match b.kind[i] {
                        BodyKind::Dynamic if b.awake[i] => self.body_position(kind, b, i, h),
                        BodyKind::Kinematic if kinematic && !b.is_link_proxy(i) => {
                            lie_group_euler_body(b, i, h)
                        }
                        _ => {}
                    }
                }
            }
        }
    }

    fn body_position(&self, kind: IntegratorKind, b: &mut BodySet, i: usize, h: f64) {
        let r0 = b.rot[i];
        let p0 = b.pos[i];
        let (rot, dp, dtheta) = if kind == IntegratorKind::ExplicitEuler {
            // Velocity at the start of the step plus the solver's change.
            let w = b.omega[i] - self.w_free[i];
            let v = b.vel[i] - self.dv[i];
            let step = exp_so3(&r0.tr_mul(&(w * h)));
            // The new body velocity is carried with the body: ω₁ = R₁ ω_b₁ = R₁ R₀ᵀ ω.
            b.omega[i] = r0 * (step * r0.tr_mul(&b.omega[i]));
            (r0 * step, v * h, w * h)
        } else {
            let mut rot = self.rot_end[i];
            let mut dtheta = self.theta[i];
            let dw = b.omega[i] - self.w_free[i];
            if dw != V3::zeros() {
                // The solver's impulses: rotate further by h Δω (world).
                rot = exp_so3(&(dw * h)) * rot;
                dtheta += dw * h;
            }
            // Constant acceleration: p₁ = p₀ + h (v₀ + v₁)/2 (= h (v − Δv/2)).
            (rot, (b.vel[i] - self.dv[i] * 0.5) * h, dtheta)
        };
        // RKMK4 is the reference integrator: its rotations are re-orthonormalised every step
        // (the velocity is stored in world axes, so `Rᵀω` inherits any drift of `RᵀR` from
        // `I`; with the periodic step alone the 1/64000 s reference settles at 1e-7).
        b.rot[i] = if kind == IntegratorKind::Rkmk4 {
            orthonormalize(&rot)
        } else {
            rot
        };
        b.pos[i] = p0 + dp;
        b.dp[i] += dp;
        b.dtheta[i] += dtheta;
    }
}

/// The second-order predictor of `Π_m`: `x = Π₀ − (h/2) f(x)` with `f(x) = ω(x) × x`, expanded
/// once about `Π₀`: `Π₀ − (h/2) f₀ + (h/2)² M₀ f₀` (error `O(h³)`).
#[inline]
fn midpoint_predictor(p0: &V3, inv_i: &V3, h: f64) -> V3 {
    let hh = 0.5 * h;
    let w0 = inv_i.component_mul(p0);
    let f0 = w0.cross(p0);
    let mf = w0.cross(&f0) - p0.cross(&inv_i.component_mul(&f0));
    p0 - f0 * hh + mf * (hh * hh)
}

/// One Newton-like iteration on the implicit midpoint equation for `x = Π_m`:
/// `G(x) = x − Π₀ + (h/2) ω × x = 0` with `ω = I⁻¹x`, applying the first-order inverse of
/// its Jacobian `J = I + (h/2)M`, `M δ = ω × δ − x × (I⁻¹δ)`; returns the squared update.
#[inline]
fn midpoint_iteration(x: &mut V3, p0: &V3, inv_i: &V3, h: f64) -> f64 {
    let hh = 0.5 * h;
    let w = inv_i.component_mul(x);
    let g = *x - p0 + w.cross(x) * hh;
    let mg = w.cross(&g) - x.cross(&inv_i.component_mul(&g));
    let d = g - mg * hh;
    *x -= d;
    d.norm_squared()
}

/// Semi-implicit Euler velocity stage (the engine's step before part 3, unchanged).
fn symplectic_velocities(b: &mut BodySet, h: f64, f: &FreeForces) {
    free_velocities(b, h, f, |b, i| {
        let (r, tq) = (b.rot[i], b.torque[i]);
        let wl = r.tr_mul(&b.omega[i]);
        let mut t = r.tr_mul(&tq);
        if f.gyroscopic {
            t -= wl.cross(&b.inertia[i].component_mul(&wl));
        }
        b.omega[i] + r * b.inv_inertia[i].component_mul(&t) * h
    });
}

/// Semi-implicit Euler with Catto's implicit gyroscopic term (the default velocity stage):
/// gravity and forces as [`symplectic_velocities`]; the body angular velocity takes the
/// torque kick `ω_b += h I⁻¹τ_b`, then, with the gyroscopic effect, one Newton step of
/// `f(ω) = I(ω − ω₀) + h ω×Iω = 0` from `ω₀` ([`implicit_gyroscopic`]). A body with neither
/// torque nor the gyroscopic term keeps its angular velocity untouched (no round trip through
/// the body frame), so such scenes cost what semi-implicit Euler costs.
fn implicit_gyroscopic_velocities(b: &mut BodySet, h: f64, f: &FreeForces) {
    free_velocities(b, h, f, |b, i| {
        let (r, tq) = (b.rot[i], b.torque[i]);
        let mut wb = r.tr_mul(&b.omega[i]) + b.inv_inertia[i].component_mul(&r.tr_mul(&tq)) * h;
        if f.gyroscopic {
            wb = implicit_gyroscopic(&wb, &b.inertia[i], h);
        }
        r * wb
    });
}

/// The velocity stage both semi-implicit steps share: for every awake body, gravity and the
/// applied force on the linear velocity; `angular(b, i)` gives the new world angular velocity
/// (rad/s) when the body has a torque or the gyroscopic effect is on (otherwise it keeps its
/// own); then the damping.
#[inline]
fn free_velocities(
    b: &mut BodySet,
    h: f64,
    f: &FreeForces,
    angular: impl Fn(&BodySet, usize) -> V3,
) {
    let g = f.gravity;
    for i in 0..b.len() {
        if !b.awake[i] {
            continue;
        }
        let im = b.inv_mass[i];
        b.vel[i] += (g + b.force[i] * im) * h;
        if f.gyroscopic || b.torque[i] != V3::zeros() {
            b.omega[i] = angular(b, i);
        }
        if let Some((ld, ad)) = f.damping {
            b.vel[i] *= ld;
            b.omega[i] *= ad;
        }
    }
}

/// One Newton step from `w0` (rad/s, body frame; principal inertia `i`, kg·m²) on Catto's
/// implicit gyroscopic equation `f(ω) = I(ω − ω₀) + h ω×Iω = 0`, Jacobian
/// `J = I + h([ω]× I − [Iω]×)`: `ω = ω₀ − J⁻¹ f(ω₀)`. A body with `ω₀ × Iω₀ = 0` keeps `ω₀`;
/// a singular `J` (never met for positive inertias and finite steps) leaves `ω₀` too.
#[inline]
fn implicit_gyroscopic(w0: &V3, i: &V3, h: f64) -> V3 {
    let iw = i.component_mul(w0);
    let res = w0.cross(&iw) * h;
    if res == V3::zeros() {
        return *w0;
    }
    let jac = M3::from_diagonal(i) + (skew(w0) * M3::from_diagonal(i) - skew(&iw)) * h;
    match jac.try_inverse() {
        Some(inv) => w0 - inv * res,
        None => *w0,
    }
}
