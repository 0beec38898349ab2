//! The pose stage of the Lie-group Euler step, `T ← T · Exp(h V)` with the body twist
//! `V = (Rᵀω, Rᵀv)`, four bodies at a time ([`Lanes`], as the contact groups are solved).
//!
//! Each lane computes bit for bit what [`lie_group_euler_body`] computes for its body: the
//! same operations in the same order (`Rᵀx` and `R x` as dot products summed left to right,
//! and `SE3::exp`'s own kernels for the coefficients' series, the rotation and the translation,
//! generic over the arithmetic; no fused multiply–add). A body that turns by 0.1 rad
//! or more in the substep, whose coefficients need a sine and a cosine, and the last bodies
//! that do not fill four lanes take the scalar step. On x86-64 the same code also runs
//! compiled for AVX2 when the processor has it ([`KernelIsa`]).

use crate::algebra::{exp_series, exp_translation, rotation_rows, se3, SE3, SERIES_THETA2};
use crate::dynamics::solver::lanes::{compiled_for, KernelIsa, Lanes, WIDTH};
use crate::dynamics::{BodyKind, BodySet};
use crate::geometry::V3;

/// A 3-vector per lane.
type LaneVec = [Lanes; 3];
/// A 3×3 matrix per lane, `m[row][column]`.
type LaneMat = [[Lanes; 3]; 3];

/// `T ← T · Exp(h V)` for body `i` (paper §4.3): the exact flow of a constant body twist.
#[inline]
pub(crate) fn lie_group_euler_body(b: &mut BodySet, i: usize, h: f64) {
    let (w, v) = (b.omega[i], b.vel[i]);
    if w == V3::zeros() && v == V3::zeros() {
        return;
    }
    let r = b.rot[i];
    let t = SE3::new(r, b.pos[i]) * SE3::exp(&se3::new(r.tr_mul(&w) * h, r.tr_mul(&v) * h));
    b.dp[i] += t.p - b.pos[i];
    b.dtheta[i] += w * h;
    b.pos[i] = t.p;
    b.rot[i] = t.r;
}

/// [`lie_group_euler_body`] for every moving body: dynamic and awake, and kinematic ones
/// (but not the proxies of tree links) when `kinematic`.
pub(crate) fn lie_group_euler_positions(b: &mut BodySet, h: f64, kinematic: bool) {
    positions_on(KernelIsa::detect(), b, h, kinematic);
}

/// The pose stage compiled for `isa`, which the processor must run. The AVX-512 processor
/// runs the AVX2 copy: compiled for AVX-512 the stage took 16 % of towers-1120's step against
/// 11 % (`perf record`), as its coefficients' kernels are not short of registers.
fn positions_on(isa: KernelIsa, b: &mut BodySet, h: f64, kinematic: bool) {
    match isa {
        // SAFETY: the processor has the instructions (`KernelIsa::detect`; AVX-512 implies
        // AVX2 there).
        #[cfg(target_arch = "x86_64")]
        KernelIsa::Avx2 | KernelIsa::Avx512 => unsafe { positions_avx2(b, h, kinematic) },
        KernelIsa::Baseline => positions(b, h, kinematic),
    }
}

compiled_for!(fn(b: &mut BodySet, h: f64, kinematic: bool) => positions:
    positions_avx2 = "avx2",
);

#[inline(always)]
fn positions(b: &mut BodySet, h: f64, kinematic: bool) {
    let mut batch = [0; WIDTH];
    let mut filled = 0;
    for i in 0..b.len() {
        let moving = match b.kind[i] {
            BodyKind::Dynamic => b.awake[i],
            BodyKind::Kinematic => kinematic && !b.is_link_proxy(i),
            BodyKind::Fixed => false,
        };
        // A body at rest keeps its pose (as the scalar step leaves it).
        if !moving || (b.omega[i] == V3::zeros() && b.vel[i] == V3::zeros()) {
            continue;
        }
        batch[filled] = i;
        filled += 1;
        if filled == WIDTH {
            four_bodies(b, &batch, h);
            filled = 0;
        }
    }
    for &i in &batch[..filled] {
        lie_group_euler_body(b, i, h);
    }
}

/// Lane `l` of each entry.
#[inline(always)]
fn lane3(x: &LaneVec, l: usize) -> V3 {
    V3::new(x[0].0[l], x[1].0[l], x[2].0[l])
}

/// `x` with its components gathered from `f` of each body.
#[inline(always)]
fn gather(bodies: &[usize; WIDTH], f: impl Fn(usize) -> V3) -> LaneVec {
    let mut x = [Lanes::splat(0.0); 3];
    for (l, &i) in bodies.iter().enumerate() {
        let v = f(i);
        for k in 0..3 {
            x[k].0[l] = v[k];
        }
    }
    x
}

/// `(a · b)` summed left to right, as nalgebra's 3-vector dot product.
#[inline(always)]
fn dot(a: [Lanes; 3], b: &LaneVec) -> Lanes {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The step of four distinct moving bodies; a lane whose turn needs the closed form
/// coefficients is left to the scalar step.
#[inline(always)]
fn four_bodies(b: &mut BodySet, bodies: &[usize; WIDTH], h: f64) {
    let mut r: LaneMat = [[Lanes::splat(0.0); 3]; 3];
    for (l, &i) in bodies.iter().enumerate() {
        for (row, rr) in r.iter_mut().enumerate() {
            for (col, x) in rr.iter_mut().enumerate() {
                x.0[l] = b.rot[i][(row, col)];
            }
        }
    }
    let w = gather(bodies, |i| b.omega[i]);
    let v = gather(bodies, |i| b.vel[i]);
    let pos = gather(bodies, |i| b.pos[i]);
    let hl = Lanes::splat(h);
    let c = Lanes::splat;
    // Body twist over the substep: `(Rᵀ x) h`, each entry a column of R dotted with x (plain
    // loops: closures and `array::map` are not inlined into the AVX2 copy).
    let mut wb = [c(0.0); 3];
    let mut vb = [c(0.0); 3];
    for k in 0..3 {
        let column = [r[0][k], r[1][k], r[2][k]];
        wb[k] = dot(column, &w) * hl;
        vb[k] = dot(column, &v) * hl;
    }
    // Exp (`SE3::exp`, with its own kernels): the coefficients' series, the rotation, the
    // translation.
    let t2 = dot(wb, &wb);
    let (a, bb, cc) = exp_series(t2, c);
    let e: LaneMat = rotation_rows(wb, t2, a, bb, c(1.0));
    let pe = exp_translation(wb, vb, bb, cc);
    // `T · Exp`: rotation `R E`, position `R pe + p`.
    let mut rn: LaneMat = [[c(0.0); 3]; 3];
    let mut pn = [c(0.0); 3];
    for row in 0..3 {
        for col in 0..3 {
            rn[row][col] = dot(r[row], &[e[0][col], e[1][col], e[2][col]]);
        }
        pn[row] = dot(r[row], &pe) + pos[row];
    }
    for (l, &i) in bodies.iter().enumerate() {
        // As in `SE3::exp`, a NaN takes the closed form, here the scalar step.
        if t2.0[l].is_nan() || t2.0[l] >= SERIES_THETA2 {
            lie_group_euler_body(b, i, h);
            continue;
        }
        let p = lane3(&pn, l);
        b.dp[i] += p - b.pos[i];
        b.dtheta[i] += b.omega[i] * h;
        b.pos[i] = p;
        for (row, rr) in rn.iter().enumerate() {
            for (col, x) in rr.iter().enumerate() {
                b.rot[i][(row, col)] = x.0[l];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::exp_so3;
    use crate::dynamics::Material;
    use crate::geometry::{Shape, M3};

    /// Bodies in every state the stage meets: at rest, slow, turning past the series' range,
    /// fixed, asleep, kinematic.
    fn bodies(n: usize) -> BodySet {
        let mut b = BodySet::default();
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for i in 0..n {
            let kind = match i % 11 {
                3 => BodyKind::Fixed,
                7 => BodyKind::Kinematic,
                _ => BodyKind::Dynamic,
            };
            let mut v3 = |s: f64| V3::new(next() * s, next() * s, next() * s);
            let rot = exp_so3(&v3(3.0));
            let pos = v3(10.0);
            let (vel, omega) = match i % 5 {
                0 => (V3::zeros(), V3::zeros()),
                1 => (v3(2.0), V3::zeros()),
                // Past the series' range at h = 1/720 s: |ω| h ≥ 0.1.
                2 => (v3(2.0), v3(300.0)),
                _ => (v3(2.0), v3(5.0)),
            };
            b.push(
                String::new(),
                kind,
                Shape::Cuboid {
                    half: V3::new(0.5, 0.25, 0.1),
                },
                Material::default(),
                1.0,
                pos,
                rot,
                vel,
                omega,
            );
            b.awake[i] = i % 13 != 5;
            b.dp[i] = v3(1e-3);
            b.dtheta[i] = v3(1e-3);
        }
        b
    }

    #[test]
    fn four_lanes_compute_what_the_scalar_step_computes() {
        let h = 1.0 / 720.0;
        for kinematic in [true, false] {
            let mut scalar = bodies(103);
            let lanes = scalar.clone();
            for i in 0..scalar.len() {
                let moving = match scalar.kind[i] {
                    BodyKind::Dynamic => scalar.awake[i],
                    BodyKind::Kinematic => kinematic,
                    BodyKind::Fixed => false,
                };
                if moving {
                    lie_group_euler_body(&mut scalar, i, h);
                }
            }
            let bits = |b: &BodySet| {
                let mut x: Vec<u64> = Vec::new();
                for i in 0..b.len() {
                    let m: &M3 = &b.rot[i];
                    x.extend(m.iter().map(|v| v.to_bits()));
                    for v in [b.pos[i], b.dp[i], b.dtheta[i]] {
                        x.extend(v.iter().map(|v| v.to_bits()));
                    }
                }
                x
            };
            // Every copy this processor runs (`KernelIsa::available`).
            for isa in KernelIsa::available() {
                let mut lanes = lanes.clone();
                positions_on(isa, &mut lanes, h, kinematic);
                assert_eq!(bits(&scalar), bits(&lanes), "{isa:?}");
            }
            // Something moved.
            assert_ne!(bits(&scalar), bits(&bodies(103)));
        }
    }
}
