//! Time of impact of a sphere swept along a straight line against a posed shape.
//!
//! The sphere's centre moves from `c0` by `d` over the step (`c(t) = c0 + t d`, `t ∈ [0, 1]`,
//! world, m); the target is posed by `(rot, pos)` (world from body) and moves by `target_d`
//! over the same step without turning. The test runs in the target's frame on the relative
//! motion `d − target_d`: the first `t` at which the sphere touches the target is the first
//! time the centre enters the target grown by the sphere's radius (its Minkowski sum with
//! the ball).
//!
//! * **Sphere, half-space, capsule, box: exact** (closed-form roots of quadratics). The
//!   rounded box is the union of the box grown by the radius along each of its three axes
//!   and of the twelve capsules around its edges; the first entry into a union is the
//!   earliest entry into a piece.
//! * **Cylinder: conservative advancement** on the exact distance to the cylinder (the
//!   centre advances by the distance left, which never passes the surface), stopping within
//!   [`CYLINDER_TOLERANCE`] of it; when advancement slows (a grazing path) the distance,
//!   convex along a line, is minimised by golden-section search and the root bracketed by
//!   bisection to the same tolerance. The time returned is never later than the true one.
//! * **Compound**: each part, the earliest hit.
//!
//! A sphere that already touches or overlaps the target at `t = 0` hits at `t = 0`, with
//! the normal of the nearest feature.

use super::{Shape, M3, V3};

/// How close to the surface (m) the cylinder's advancement stops: the sphere at the
/// returned time is at most this far from touching.
pub(crate) const CYLINDER_TOLERANCE: f64 = 1e-10;

/// Conservative advancement steps on a cylinder before the bracketing search takes over.
const ADVANCE_STEPS: usize = 24;

/// Where and when a swept sphere first touches a shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// Fraction of the step at which the sphere first touches, in `[0, 1]` (–).
    pub(crate) t: f64,
    /// Unit normal at the impact, world, from the target towards the sphere's centre.
    pub(crate) normal: V3,
    /// The touching point on the target's surface at time `t` (m, world; the target posed
    /// where it is at `t`).
    pub(crate) point: V3,
    /// Part of a compound target that is hit (0 for a primitive).
    pub(crate) part: u16,
}

/// First time in `[0, 1]` at which a sphere of `radius` (m) whose centre moves from `c0` by
/// `d` (m, world) touches `shape` posed by `(rot, pos)` (world from body) and moving by
/// `target_d` (m, world) without turning; `None` when it does not within the step.
#[allow(clippy::too_many_arguments)]
pub fn sphere_cast(
    c0: &V3,
    d: &V3,
    radius: f64,
    shape: &Shape,
    rot: &M3,
    pos: &V3,
    target_d: &V3,
) -> Option<Impact> {
    match shape {
        Shape::Compound(c) => {
            let mut best: Option<Impact> = None;
            for (k, part) in c.parts().iter().enumerate() {
                let (r, p) = (rot * part.rot, pos + rot * part.pos);
                if let Some(mut hit) = sphere_cast(c0, d, radius, &part.shape, &r, &p, target_d) {
                    if best.is_none_or(|b| hit.t < b.t) {
                        hit.part = k as u16;
                        best = Some(hit);
                    }
                }
            }
            best
        }
        s => {
            // Target frame, relative motion.
            let cl = rot.tr_mul(&(c0 - pos));
            let dl = rot.tr_mul(&(d - target_d));
            let (t, n_local, q_local) = cast_local(&cl, &dl, radius, s)?;
            Some(Impact {
                t,
                normal: rot * n_local,
                point: pos + target_d * t + rot * q_local,
                part: 0,
            })
        }
    }
}

/// The cast in the primitive's frame: `(t, normal, point on the surface)`.
fn cast_local(c: &V3, d: &V3, r: f64, shape: &Shape) -> Option<(f64, V3, V3)> {
    match *shape {
        Shape::Sphere { radius } => {
            let t = ray_sphere(c, d, &V3::zeros(), r + radius)?;
            let x = c + d * t;
            let n = unit_or(&x, &V3::z());
            Some((t, n, n * radius))
        }
        Shape::HalfSpace { normal } => {
            let n = unit_or(&normal, &V3::z());
            let s0 = n.dot(c) - r;
            let t = if s0 <= 0.0 {
                0.0
            } else {
                let closing = -n.dot(d);
                if closing <= 0.0 || s0 > closing {
                    return None;
                }
                s0 / closing
            };
            let x = c + d * t;
            Some((t, n, x - n * (n.dot(&x))))
        }
        Shape::Capsule {
            radius,
            half_height,
        } => {
            let (a, b) = (
                V3::new(0.0, 0.0, -half_height),
                V3::new(0.0, 0.0, half_height),
            );
            let t = ray_capsule(c, d, &a, &b, r + radius)?;
            let x = c + d * t;
            let core = V3::new(0.0, 0.0, x.z.clamp(-half_height, half_height));
            let n = unit_or(&(x - core), &V3::x());
            Some((t, n, core + n * radius))
        }
        Shape::Cuboid { half } => {
            let t = ray_rounded_box(c, d, &half, r)?;
            let (n, q) = box_feature(&(c + d * t), &half);
            Some((t, n, q))
        }
        Shape::Cylinder {
            radius,
            half_height,
        } => {
            let t = cast_cylinder(c, d, r, radius, half_height)?;
            let (n, q) = cylinder_feature(&(c + d * t), radius, half_height);
            Some((t, n, q))
        }
        // The caller splits compounds into their parts.
        Shape::Compound(_) => None,
    }
}

/// `v / |v|`, or `fallback` for a (near) zero vector.
fn unit_or(v: &V3, fallback: &V3) -> V3 {
    let n = v.norm();
    if n > 1e-300 {
        v / n
    } else {
        *fallback
    }
}

/// First `t ∈ [0, 1]` with `|c + t d − q| ≤ rr`.
fn ray_sphere(c: &V3, d: &V3, q: &V3, rr: f64) -> Option<f64> {
    let m = c - q;
    let cc = m.norm_squared() - rr * rr;
    if cc <= 0.0 {
        return Some(0.0);
    }
    let b = m.dot(d);
    if b >= 0.0 {
        return None;
    }
    let a = d.norm_squared();
    let disc = b * b - a * cc;
    if disc < 0.0 {
        return None;
    }
    // The smaller root, in the cancellation-free form cc / (−b + √disc).
    let t = cc / (-b + disc.sqrt());
    (t <= 1.0).then_some(t)
}

/// First `t ∈ [0, 1]` at which `c + t d` comes within `rr` of the segment `[a, b]`.
fn ray_capsule(c: &V3, d: &V3, a: &V3, b: &V3, rr: f64) -> Option<f64> {
    let ax = b - a;
    let l2 = ax.norm_squared();
    let m = c - a;
    let s0 = (m.dot(&ax) / l2).clamp(0.0, 1.0);
    if (m - ax * s0).norm_squared() <= rr * rr {
        return Some(0.0);
    }
    let mut best = ray_sphere(c, d, a, rr);
    if let Some(t) = ray_sphere(c, d, b, rr) {
        best = Some(best.map_or(t, |u: f64| u.min(t)));
    }
    // The side: the infinite cylinder around the axis, within the segment.
    let dp = d - ax * (d.dot(&ax) / l2);
    let mp = m - ax * (m.dot(&ax) / l2);
    let aa = dp.norm_squared();
    if aa > 0.0 {
        let bb = mp.dot(&dp);
        let cc = mp.norm_squared() - rr * rr;
        let disc = bb * bb - aa * cc;
        if bb < 0.0 && cc > 0.0 && disc >= 0.0 {
            let t = cc / (-bb + disc.sqrt());
            let s = (m + d * t).dot(&ax) / l2;
            if t <= 1.0 && (0.0..=1.0).contains(&s) {
                best = Some(best.map_or(t, |u| u.min(t)));
            }
        }
    }
    best
}

/// Entry time into the box `|x_i| ≤ e_i` of the segment `c + t d`, `t ∈ [0, 1]`.
fn ray_aabb(c: &V3, d: &V3, e: &V3) -> Option<f64> {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    for i in 0..3 {
        if d[i] == 0.0 {
            if c[i].abs() > e[i] {
                return None;
            }
            continue;
        }
        let inv = 1.0 / d[i];
        let (mut t0, mut t1) = ((-e[i] - c[i]) * inv, (e[i] - c[i]) * inv);
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        lo = lo.max(t0);
        hi = hi.min(t1);
        if lo > hi {
            return None;
        }
    }
    Some(lo)
}

/// First `t ∈ [0, 1]` at which a sphere of radius `r` at `c + t d` touches the box of half
/// extents `h` (exact).
fn ray_rounded_box(c: &V3, d: &V3, h: &V3, r: f64) -> Option<f64> {
    // Quick reject: the box grown by r on every axis contains the rounded box.
    ray_aabb(c, d, &(h + V3::repeat(r)))?;
    let outside = (c.abs() - h).sup(&V3::zeros());
    if outside.norm_squared() <= r * r {
        return Some(0.0);
    }
    let mut best: Option<f64> = None;
    let mut keep = |t: Option<f64>| {
        if let Some(t) = t {
            best = Some(best.map_or(t, |u: f64| u.min(t)));
        }
    };
    for i in 0..3 {
        let mut e = *h;
        e[i] += r;
        keep(ray_aabb(c, d, &e));
    }
    // The twelve edges: along axis i, at the four sign combinations of the other two.
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        for (sj, sk) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
            let mut a = V3::zeros();
            a[j] = sj * h[j];
            a[k] = sk * h[k];
            let mut b = a;
            a[i] = -h[i];
            b[i] = h[i];
            keep(ray_capsule(c, d, &a, &b, r));
        }
    }
    best
}

/// Outward normal and nearest surface point of the box of half extents `h` for a point `x`
/// (box frame).
fn box_feature(x: &V3, h: &V3) -> (V3, V3) {
    let q = V3::new(
        x.x.clamp(-h.x, h.x),
        x.y.clamp(-h.y, h.y),
        x.z.clamp(-h.z, h.z),
    );
    let diff = x - q;
    if diff.norm_squared() > 1e-24 {
        return (diff.normalize(), q);
    }
    // Inside: the nearest face.
    let mut k = 0;
    let mut best = f64::INFINITY;
    for i in 0..3 {
        let pen = h[i] - x[i].abs();
        if pen < best {
            best = pen;
            k = i;
        }
    }
    let sgn = if x[k] >= 0.0 { 1.0 } else { -1.0 };
    let mut q = *x;
    q[k] = sgn * h[k];
    (V3::ith(k, sgn), q)
}

/// Outward normal and nearest surface point of the cylinder `(radius, hh)` along `z` for a
/// point `x` (cylinder frame).
fn cylinder_feature(x: &V3, radius: f64, hh: f64) -> (V3, V3) {
    let rho = (x.x * x.x + x.y * x.y).sqrt();
    let radial = if rho > 1e-300 {
        V3::new(x.x / rho, x.y / rho, 0.0)
    } else {
        V3::x()
    };
    let q = radial * rho.min(radius) + V3::new(0.0, 0.0, x.z.clamp(-hh, hh));
    let diff = x - q;
    if diff.norm_squared() > 1e-24 {
        return (diff.normalize(), q);
    }
    // Inside: through the side or the nearer cap.
    if radius - rho < hh - x.z.abs() {
        (radial, radial * radius + V3::new(0.0, 0.0, x.z))
    } else {
        let s = if x.z >= 0.0 { 1.0 } else { -1.0 };
        (V3::new(0.0, 0.0, s), V3::new(x.x, x.y, s * hh))
    }
}

/// Distance (m) from `x` to the cylinder `(radius, hh)` along `z` (0 inside).
fn cylinder_distance(x: &V3, radius: f64, hh: f64) -> f64 {
    let radial = ((x.x * x.x + x.y * x.y).sqrt() - radius).max(0.0);
    let axial = (x.z.abs() - hh).max(0.0);
    (radial * radial + axial * axial).sqrt()
}

/// First `t ∈ [0, 1]` at which a sphere of radius `r` at `c + t d` comes within
/// [`CYLINDER_TOLERANCE`] of the cylinder `(radius, hh)`; never later than the true time.
fn cast_cylinder(c: &V3, d: &V3, r: f64, radius: f64, hh: f64) -> Option<f64> {
    let f = |t: f64| cylinder_distance(&(c + d * t), radius, hh) - r;
    if f(0.0) <= CYLINDER_TOLERANCE {
        return Some(0.0);
    }
    // Quick reject and a start: the capped cylinder grown by r contains the target grown.
    let grown = V3::new(radius + r, radius + r, hh + r);
    let mut t = ray_aabb(c, d, &grown)?;
    let len = d.norm();
    let mut ft = f(t);
    for _ in 0..ADVANCE_STEPS {
        if ft <= CYLINDER_TOLERANCE {
            return Some(t);
        }
        let next = t + ft / len;
        if next > 1.0 {
            return (f(1.0) <= CYLINDER_TOLERANCE).then_some(1.0);
        }
        let fnext = f(next);
        if fnext >= ft {
            // The distance along a line is convex: once it stops falling it never returns.
            return None;
        }
        (t, ft) = (next, fnext);
    }
    // Grazing: find the closest approach on [t, 1], then the first root before it.
    let (mut lo, mut hi) = (t, 1.0);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    while (hi - lo) * len > CYLINDER_TOLERANCE {
        if f1 <= CYLINDER_TOLERANCE || f2 <= CYLINDER_TOLERANCE {
            break;
        }
        if f1 < f2 {
            (hi, x2, f2) = (x2, x1, f1);
            x1 = hi - g * (hi - lo);
            f1 = f(x1);
        } else {
            (lo, x1, f1) = (x1, x2, f2);
            x2 = lo + g * (hi - lo);
            f2 = f(x2);
        }
    }
    let inside = if f1 <= CYLINDER_TOLERANCE {
        x1
    } else if f2 <= CYLINDER_TOLERANCE {
        x2
    } else {
        let m = 0.5 * (lo + hi);
        if f(m) > CYLINDER_TOLERANCE {
            return None;
        }
        m
    };
    // f(t) > tol ≥ f(inside), f decreasing on [t, inside]: bisect.
    let (mut a, mut b) = (t, inside);
    while (b - a) * len > CYLINDER_TOLERANCE * 0.5 {
        let m = 0.5 * (a + b);
        if f(m) <= CYLINDER_TOLERANCE {
            b = m;
        } else {
            a = m;
        }
    }
    Some(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Compound, Material, Part};
    use std::sync::Arc;

    const R: f64 = 0.0175;

    fn still() -> V3 {
        V3::zeros()
    }

    fn cast(c0: V3, d: V3, shape: &Shape) -> Option<Impact> {
        sphere_cast(&c0, &d, R, shape, &M3::identity(), &V3::zeros(), &still())
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    fn boxed() -> Shape {
        Shape::Cuboid {
            half: V3::new(0.05, 0.1, 0.2),
        }
    }

    #[test]
    fn head_on_into_each_shape() {
        // From x = −0.5 at 1 m per step towards +x; every target's face at x = −0.05.
        let shapes = [
            boxed(),
            Shape::Sphere { radius: 0.05 },
            Shape::HalfSpace { normal: -V3::x() },
            Shape::Cylinder {
                radius: 0.05,
                half_height: 0.3,
            },
            Shape::Capsule {
                radius: 0.05,
                half_height: 0.3,
            },
        ];
        for s in &shapes {
            if let Shape::HalfSpace { .. } = s {
                // n·x ≤ 0 with n = −x: the solid x ≥ 0, posed at x = −0.05.
                let hit = sphere_cast(
                    &V3::new(-0.5, 0.0, 0.0),
                    &V3::new(1.0, 0.0, 0.0),
                    R,
                    s,
                    &M3::identity(),
                    &V3::new(-0.05, 0.0, 0.0),
                    &still(),
                )
                .unwrap();
                assert!(close(hit.t, 0.45 - R, 1e-12), "{s:?}: {}", hit.t);
                assert!((hit.normal + V3::x()).norm() < 1e-12);
                assert!((hit.point - V3::new(-0.05, 0.0, 0.0)).norm() < 1e-12);
                continue;
            }
            // Cylinders and capsules lie along y, so that their side faces the ball.
            let rot = if matches!(s, Shape::Cylinder { .. } | Shape::Capsule { .. }) {
                crate::algebra::exp_so3(&(V3::x() * std::f64::consts::FRAC_PI_2))
            } else {
                M3::identity()
            };
            let hit = sphere_cast(
                &V3::new(-0.5, 0.0, 0.0),
                &V3::new(1.0, 0.0, 0.0),
                R,
                s,
                &rot,
                &V3::zeros(),
                &still(),
            )
            .unwrap();
            let tol = if matches!(s, Shape::Cylinder { .. }) {
                CYLINDER_TOLERANCE
            } else {
                1e-12
            };
            assert!(close(hit.t, 0.45 - R, tol), "{s:?}: {}", hit.t);
            assert!(
                (hit.normal + V3::x()).norm() < 1e-9,
                "{s:?}: {}",
                hit.normal
            );
            assert!((hit.point - V3::new(-0.05, 0.0, 0.0)).norm() < 1e-9);
        }
    }

    #[test]
    fn grazing_a_box_face_at_the_radius_plus_and_minus_epsilon() {
        // Along x past the face y = 0.1 of the box; the centre at y = 0.1 + R ± ε.
        let eps = 1e-9;
        let below = cast(V3::new(-0.5, 0.1 + R - eps, 0.0), V3::x(), &boxed()).unwrap();
        // Touches where the face begins: x = −0.05 − √(R² − (R − ε)²) ≈ −0.05 − √(2Rε).
        let expect = 0.45 - (R * R - (R - eps) * (R - eps)).sqrt();
        assert!(close(below.t, expect, 1e-9), "{} vs {expect}", below.t);
        assert!(cast(V3::new(-0.5, 0.1 + R + eps, 0.0), V3::x(), &boxed()).is_none());
    }

    #[test]
    fn a_box_edge_and_a_box_corner() {
        // Edge along z at (x, y) = (−0.05, 0.1); the centre's path at y = 0.1 + R/2 hits
        // it where (x + 0.05)² + (R/2)² = R², x < −0.05.
        let hit = cast(V3::new(-0.5, 0.1 + 0.5 * R, 0.0), V3::x(), &boxed()).unwrap();
        let dx = (R * R - 0.25 * R * R).sqrt();
        assert!(close(hit.t, 0.45 - dx, 1e-12));
        let n = V3::new(-dx, 0.5 * R, 0.0) / R;
        assert!((hit.normal - n).norm() < 1e-9, "{}", hit.normal);
        assert!((hit.point - V3::new(-0.05, 0.1, 0.0)).norm() < 1e-12);
        // Corner (0.05, 0.1, 0.2) approached along the diagonal.
        let dir = V3::new(1.0, 1.0, 1.0).normalize();
        let corner = V3::new(0.05, 0.1, 0.2);
        let hit = cast(corner + dir * 0.5, -dir, &boxed()).unwrap();
        assert!(close(hit.t, 0.5 - R, 1e-12));
        assert!((hit.normal - dir).norm() < 1e-12);
        assert!((hit.point - corner).norm() < 1e-12);
    }

    #[test]
    fn a_cylinder_rim_and_cap() {
        let cyl = Shape::Cylinder {
            radius: 0.05,
            half_height: 0.1,
        };
        // Down onto the cap.
        let hit = cast(V3::new(0.01, 0.0, 0.5), V3::new(0.0, 0.0, -1.0), &cyl).unwrap();
        assert!(close(hit.t, 0.4 - R, 2.0 * CYLINDER_TOLERANCE));
        assert!((hit.normal - V3::z()).norm() < 1e-9);
        // Down past the rim: centre at radial 0.05 + R/2, touches the rim circle where
        // (z − 0.1)² + (R/2)² = R².
        let hit = cast(V3::new(0.05 + 0.5 * R, 0.0, 0.5), -V3::z(), &cyl).unwrap();
        let dz = (0.75f64).sqrt() * R;
        assert!(
            close(hit.t, 0.4 - dz, 2.0 * CYLINDER_TOLERANCE),
            "{}",
            hit.t
        );
        assert!((hit.normal - V3::new(0.5, 0.0, 0.75f64.sqrt())).norm() < 1e-6);
        assert!((hit.point - V3::new(0.05, 0.0, 0.1)).norm() < 1e-6);
        // Past the rim at R + 1 µm: a miss; at R − 1 µm: a hit.
        assert!(cast(V3::new(0.05 + R + 1e-6, 0.0, 0.5), -V3::z(), &cyl).is_none());
        assert!(cast(V3::new(0.05 + R - 1e-6, 0.0, 0.5), -V3::z(), &cyl).is_some());
    }

    #[test]
    fn a_miss_by_a_millimetre() {
        let gap = 1e-3;
        let y = 0.1 + R + gap;
        assert!(cast(V3::new(-0.5, y, 0.0), V3::x(), &boxed()).is_none());
        let ball = Shape::Sphere { radius: 0.05 };
        assert!(cast(V3::new(-0.5, 0.05 + R + gap, 0.0), V3::x(), &ball).is_none());
        let cap = Shape::Capsule {
            radius: 0.05,
            half_height: 0.3,
        };
        assert!(cast(V3::new(-0.5, 0.05 + R + gap, 0.0), V3::x(), &cap).is_none());
        let cyl = Shape::Cylinder {
            radius: 0.05,
            half_height: 0.3,
        };
        assert!(cast(V3::new(-0.5, 0.05 + R + gap, 0.0), V3::x(), &cyl).is_none());
        // Too short: stops 1 mm before the face.
        assert!(cast(
            V3::new(-0.5, 0.0, 0.0),
            V3::x() * (0.45 - R - gap),
            &boxed()
        )
        .is_none());
    }

    #[test]
    fn a_moving_target_and_touching_at_the_start() {
        // The ball still, a box coming at it at 1 m per step: the relative motion of the
        // head-on case.
        let hit = sphere_cast(
            &V3::new(-0.5, 0.0, 0.0),
            &V3::zeros(),
            R,
            &boxed(),
            &M3::identity(),
            &V3::zeros(),
            &(-V3::x()),
        )
        .unwrap();
        assert!(close(hit.t, 0.45 - R, 1e-12));
        // The point where the face is at that time.
        assert!((hit.point - V3::new(-0.05 - hit.t, 0.0, 0.0)).norm() < 1e-12);
        let touching = cast(V3::new(-0.05 - R + 1e-6, 0.0, 0.0), V3::x(), &boxed()).unwrap();
        assert_eq!(touching.t, 0.0);
    }

    #[test]
    fn a_compound_reports_its_first_part() {
        let part = |x: f64| Part {
            shape: Shape::Cuboid {
                half: V3::repeat(0.01),
            },
            rot: M3::identity(),
            pos: V3::new(x, 0.0, 0.0),
            material: Material::default(),
        };
        let c = Compound::from_parts(vec![part(0.2), part(0.0)]).unwrap();
        let s = Shape::Compound(Arc::new(c));
        let hit = cast(V3::new(-0.5, 0.0, 0.0), V3::x(), &s).unwrap();
        assert_eq!(hit.part, 1);
        assert!(close(hit.t, 0.49 - R, 1e-12));
    }

    mod against_sampling {
        use super::*;
        use proptest::prelude::*;

        /// Samples of the brute-force sweep.
        const SAMPLES: usize = 4000;

        fn shape(kind: u8, a: f64, b: f64, c: f64) -> Shape {
            match kind {
                0 => Shape::Cuboid {
                    half: V3::new(a, b, c),
                },
                1 => Shape::Sphere { radius: a },
                2 => Shape::Capsule {
                    radius: a,
                    half_height: b,
                },
                3 => Shape::Cylinder {
                    radius: a,
                    half_height: b,
                },
                4 => Shape::HalfSpace { normal: V3::z() },
                _ => {
                    let part = |shape: Shape, x: f64| Part {
                        shape,
                        rot: crate::algebra::exp_so3(&V3::new(0.3, -0.2, 0.5)),
                        pos: V3::new(x, 0.2 * x, -0.1 * x),
                        material: Material::default(),
                    };
                    let c = Compound::from_parts(vec![
                        part(
                            Shape::Cuboid {
                                half: V3::new(a, b, c),
                            },
                            -0.08,
                        ),
                        part(
                            Shape::Capsule {
                                radius: c,
                                half_height: a,
                            },
                            0.08,
                        ),
                    ])
                    .unwrap();
                    Shape::Compound(Arc::new(c))
                }
            }
        }

        fn v3(r: f64) -> impl Strategy<Value = V3> {
            (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| V3::new(x, y, z))
        }

        proptest! {
            #![proptest_config(ProptestConfig::with_cases(512))]
            #[test]
            fn the_cast_agrees_with_a_fine_sampling_of_the_sweep(
                kind in 0u8..6,
                (a, b, c) in (0.005..0.1f64, 0.005..0.1f64, 0.005..0.1f64),
                axis in v3(2.0),
                pos in v3(0.05),
                c0 in v3(0.3),
                d in v3(0.4),
                moving in any::<bool>(),
                td in v3(0.2),
                radius in 0.002..0.04f64,
            ) {
                let s = shape(kind, a, b, c);
                let rot = crate::algebra::exp_so3(&axis);
                let td = if moving { td } else { V3::zeros() };
                let dist = |t: f64| {
                    let x = c0 + d * t - (pos + td * t);
                    s.signed_distance(&rot.tr_mul(&x)) - radius
                };
                let first = (0..=SAMPLES).find(|&k| dist(k as f64 / SAMPLES as f64) <= 0.0);
                let hit = sphere_cast(&c0, &d, radius, &s, &rot, &pos, &td);
                let step = 1.0 / SAMPLES as f64;
                let len = (d - td).norm();
                match (first, hit) {
                    (Some(0), Some(h)) => prop_assert_eq!(h.t, 0.0),
                    (Some(k), Some(h)) => {
                        let tk = k as f64 * step;
                        // The first contact lies between the last free sample and the first
                        // touching one (CYLINDER_TOLERANCE early at most).
                        let early = 2.0 * CYLINDER_TOLERANCE / len;
                        prop_assert!(h.t <= tk + 1e-12 && h.t > tk - step - early,
                            "cast {} vs samples ({}, {}]", h.t, tk - step, tk);
                    }
                    (Some(k), None) => prop_assert!(false, "missed a hit at sample {k}"),
                    (None, Some(h)) => {
                        // Only a graze between two samples: the path comes within one
                        // sample's travel of touching.
                        let near = (0..=SAMPLES).map(|k| dist(k as f64 * step)).fold(f64::INFINITY, f64::min);
                        prop_assert!(near <= len * step, "hit at {} but {near} m away", h.t);
                    }
                    (None, None) => {}
                }
                if let Some(h) = hit.filter(|h| h.t > 0.0) {
                    // Touching at t: the centre at the radius from the point, along the normal.
                    let centre = c0 + d * h.t;
                    let tol = 1e-9 + 4.0 * CYLINDER_TOLERANCE;
                    prop_assert!(dist(h.t).abs() <= tol, "distance {} at t {}", dist(h.t), h.t);
                    prop_assert!(((centre - h.point).norm() - radius).abs() <= tol);
                    prop_assert!((h.normal - (centre - h.point) / radius).norm() <= 1e-6);
                }
            }
        }
    }
}
