//! Contacts for the pairs other than box–box: sphere, capsule, cylinder, half-space.
//!
//! Each routine writes the manifold normal from its first shape to its second and returns
//! whether a point closer than `margin` (m) exists. Poses are world from body: rotation `r`
//! (columns are the body axes), position `p` (m).

use super::{Manifold, M3, V3};

/// Sphere–sphere.
pub(crate) fn sphere_sphere(
    pa: &V3,
    ra: f64,
    pb: &V3,
    rb: f64,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    out.len = 0;
    let d = pb - pa;
    let dist = d.norm();
    let s = dist - ra - rb;
    if s > margin {
        return false;
    }
    let n = if dist > 1e-12 { d / dist } else { V3::z() };
    out.normal = n;
    out.push(pa + n * (ra + 0.5 * s), s);
    true
}

/// Closest point of box `(r, p, half)` to `c` and the outward normal there; also the signed
/// distance from `c` to the box surface (negative inside).
fn box_closest(r: &M3, p: &V3, half: &V3, c: &V3) -> (V3, V3, f64) {
    let cl = r.tr_mul(&(c - p));
    let q = V3::new(
        cl.x.clamp(-half.x, half.x),
        cl.y.clamp(-half.y, half.y),
        cl.z.clamp(-half.z, half.z),
    );
    let diff = cl - q;
    let dist2 = diff.norm_squared();
    if dist2 > 1e-24 {
        let dist = dist2.sqrt();
        (p + r * q, r * (diff / dist), dist)
    } else {
        // Inside: leave through the nearest face.
        let mut k = 0;
        let mut best = f64::INFINITY;
        for i in 0..3 {
            let pen = half[i] - cl[i].abs();
            if pen < best {
                best = pen;
                k = i;
            }
        }
        let sgn = if cl[k] >= 0.0 { 1.0 } else { -1.0 };
        let mut q = cl;
        q[k] = sgn * half[k];
        let nl = V3::ith(k, sgn);
        (p + r * q, r * nl, -best)
    }
}

/// Box (A) – sphere (B).
pub(crate) fn box_sphere(
    r: &M3,
    p: &V3,
    half: &V3,
    c: &V3,
    radius: f64,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    out.len = 0;
    let (q, n, dist) = box_closest(r, p, half, c);
    let s = dist - radius;
    if s > margin {
        return false;
    }
    out.normal = n;
    out.push(q + n * (0.5 * s), s);
    true
}

/// Half-space (A: outward normal `n` world, plane offset `o = n·x` on the boundary) –
/// points `pts` of B swept by `radius`; keeps the 4 deepest within `margin`.
fn plane_points(n: &V3, o: f64, pts: &[V3], radius: f64, margin: f64, out: &mut Manifold) -> bool {
    out.len = 0;
    out.normal = *n;
    let mut buf = [(V3::zeros(), 0.0); 16];
    let mut m = 0;
    for x in pts {
        let s = n.dot(x) - o - radius;
        if s <= margin && m < buf.len() {
            buf[m] = (x - n * (radius + 0.5 * s), s);
            m += 1;
        }
    }
    if m <= 4 {
        for (p, s) in &buf[..m] {
            out.push(*p, *s);
        }
    } else {
        // Deepest first, then the farthest spread (same rule as box clipping).
        buf[..m].sort_by(|a, b| a.1.total_cmp(&b.1));
        let first = buf[0];
        out.push(first.0, first.1);
        let mut far = 1;
        for k in 1..m {
            if (buf[k].0 - first.0).norm_squared() > (buf[far].0 - first.0).norm_squared() {
                far = k;
            }
        }
        out.push(buf[far].0, buf[far].1);
        let e = buf[far].0 - first.0;
        let (mut kp, mut kn, mut ap, mut an) = (0, 0, 0.0, 0.0);
        for (k, b) in buf[..m].iter().enumerate() {
            let a = e.cross(&(b.0 - first.0)).dot(n);
            if a > ap {
                ap = a;
                kp = k;
            }
            if a < an {
                an = a;
                kn = k;
            }
        }
        if ap > 0.0 {
            out.push(buf[kp].0, buf[kp].1);
        }
        if an < 0.0 {
            out.push(buf[kn].0, buf[kn].1);
        }
    }
    out.len > 0
}

/// Half-space (A) – box (B): the corners of the face turned towards the plane.
pub(crate) fn plane_box(
    n: &V3,
    o: f64,
    r: &M3,
    p: &V3,
    half: &V3,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    // The incident face: the one whose outward normal points most against the plane's. Its
    // four corners hold the deepest one; a corner of the opposite face is never a contact,
    // even where the box is thinner than the margin (a domino lying flat).
    let nl = r.tr_mul(n);
    let axis = nl.iamax();
    let face = if nl[axis] > 0.0 { -1.0 } else { 1.0 };
    let mut c = [V3::zeros(); 4];
    let mut m = 0;
    for k in 0..8 {
        let s = V3::new(
            if k & 1 == 0 { -1.0 } else { 1.0 },
            if k & 2 == 0 { -1.0 } else { 1.0 },
            if k & 4 == 0 { -1.0 } else { 1.0 },
        );
        if s[axis] == face {
            c[m] = p + r * half.component_mul(&s);
            m += 1;
        }
    }
    plane_points(n, o, &c[..m], 0.0, margin, out)
}

/// Half-space (A) – sphere (B).
pub(crate) fn plane_sphere(
    n: &V3,
    o: f64,
    c: &V3,
    radius: f64,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    plane_points(n, o, std::slice::from_ref(c), radius, margin, out)
}

/// Half-space (A) – capsule (B): the two segment ends.
#[allow(clippy::too_many_arguments)]
pub(crate) fn plane_capsule(
    n: &V3,
    o: f64,
    r: &M3,
    p: &V3,
    radius: f64,
    hh: f64,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    let a = r.column(2) * hh;
    plane_points(n, o, &[p + a, p - a], radius, margin, out)
}

/// Half-space (A) – cylinder (B): 8 points on each cap rim.
#[allow(clippy::too_many_arguments)]
pub(crate) fn plane_cylinder(
    n: &V3,
    o: f64,
    r: &M3,
    p: &V3,
    radius: f64,
    hh: f64,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    let mut pts = [V3::zeros(); 16];
    let (ex, ey, ez) = (r.column(0), r.column(1), r.column(2));
    for k in 0..8 {
        let t = k as f64 * std::f64::consts::FRAC_PI_4;
        let (s, c) = crate::transcendental::sin_cos(t);
        let rim = (ex * c + ey * s) * radius;
        pts[2 * k] = p + rim + ez * hh;
        pts[2 * k + 1] = p + rim - ez * hh;
    }
    plane_points(n, o, &pts, 0.0, margin, out)
}

/// Closest point on segment `[a0, a1]` to `x`.
fn segment_closest(a0: &V3, a1: &V3, x: &V3) -> V3 {
    let e = a1 - a0;
    let l2 = e.norm_squared();
    let t = if l2 > 1e-24 {
        ((x - a0).dot(&e) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    a0 + e * t
}

/// Closest points of segments `[p0, p1]` and `[q0, q1]`.
fn segment_segment(p0: &V3, p1: &V3, q0: &V3, q1: &V3) -> (V3, V3) {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    let (s, t);
    if a <= 1e-24 && e <= 1e-24 {
        return (*p0, *q0);
    }
    if a <= 1e-24 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= 1e-24 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let den = a * e - b * b;
            let s0 = if den > 1e-18 {
                ((b * f - c * e) / den).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            } else {
                t = t0;
                s = s0;
            }
        }
    }
    (p0 + d1 * s, q0 + d2 * t)
}

/// Capsule (A) – sphere (B).
#[allow(clippy::too_many_arguments)]
pub(crate) fn capsule_sphere(
    r: &M3,
    p: &V3,
    radius: f64,
    hh: f64,
    c: &V3,
    rb: f64,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    let a = r.column(2) * hh;
    let q = segment_closest(&(p - a), &(p + a), c);
    sphere_sphere(&q, radius, c, rb, margin, out)
}

/// Capsule (A) – capsule (B).
#[allow(clippy::too_many_arguments)]
pub(crate) fn capsule_capsule(
    ra: &M3,
    pa: &V3,
    rad_a: f64,
    hha: f64,
    rb: &M3,
    pb: &V3,
    rad_b: f64,
    hhb: f64,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    let ea = ra.column(2) * hha;
    let eb = rb.column(2) * hhb;
    let (qa, qb) = segment_segment(&(pa - ea), &(pa + ea), &(pb - eb), &(pb + eb));
    sphere_sphere(&qa, rad_a, &qb, rad_b, margin, out)
}

/// Signed distance from `cl` (box frame) to the box `[-half, half]` (m, negative inside).
fn box_signed_distance(cl: &V3, half: &V3) -> f64 {
    let out = V3::new(
        (cl.x.abs() - half.x).max(0.0),
        (cl.y.abs() - half.y).max(0.0),
        (cl.z.abs() - half.z).max(0.0),
    );
    let outside = out.norm_squared();
    if outside > 0.0 {
        outside.sqrt()
    } else {
        (cl.x.abs() - half.x)
            .max(cl.y.abs() - half.y)
            .max(cl.z.abs() - half.z)
    }
}

/// The point of segment `a + (b − a) t`, `t ∈ [t0, t1]` (box frame), deepest in the box
/// `[-half, half]`: the least signed distance along it, found by golden-section search. The
/// signed distance to a convex body is convex along a line, so the search converges to the
/// deepest point; it stops once the bracket is shorter than `DEEPEST_TOLERANCE_M`.
fn segment_deepest_in_box(a: &V3, b: &V3, t0: f64, t1: f64, half: &V3) -> V3 {
    /// Length of the final bracket along the segment, m: far below any contact's scale.
    const DEEPEST_TOLERANCE_M: f64 = 1e-8;
    /// Bound on the steps for any segment's length (a 1 km segment takes 57).
    const MAX_STEPS: usize = 80;
    let inv_phi = 0.5 * (5f64.sqrt() - 1.0);
    let d = b - a;
    let at = |t: f64| a + d * t;
    let f = |t: f64| box_signed_distance(&at(t), half);
    let length = d.norm();
    let (mut lo, mut hi) = (t0, t1);
    let (mut x1, mut x2) = (hi - inv_phi * (hi - lo), lo + inv_phi * (hi - lo));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..MAX_STEPS {
        if (hi - lo) * length <= DEEPEST_TOLERANCE_M {
            break;
        }
        if f1 <= f2 {
            hi = x2;
            (x2, f2) = (x1, f1);
            x1 = hi - inv_phi * (hi - lo);
            f1 = f(x1);
        } else {
            lo = x1;
            (x1, f1) = (x2, f2);
            x2 = lo + inv_phi * (hi - lo);
            f2 = f(x2);
        }
    }
    at(0.5 * (lo + hi))
}

/// The axis of the box `[-half, half]` whose face the point `x` (box frame) leaves by: the
/// largest component of its outward direction, outside; the face of least depth, inside.
fn reference_axis(x: &V3, half: &V3) -> usize {
    let excess = x.abs() - half;
    let out = excess.map(|e| e.max(0.0));
    let key = if out.norm_squared() > 0.0 {
        out
    } else {
        excess
    };
    let mut k = 0;
    for i in 1..3 {
        if key[i] > key[k] {
            k = i;
        }
    }
    k
}

/// The parameter range `[t0, t1] ⊆ [0, 1]` of the segment `a + (b − a) t` inside the box
/// `[-half, half]`, all in the box's frame (slab clipping), or `None` where it misses.
fn segment_in_box(a: &V3, b: &V3, half: &V3) -> Option<(f64, f64)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for i in 0..3 {
        if d[i].abs() < 1e-15 {
            if a[i].abs() > half[i] {
                return None;
            }
        } else {
            let inv = 1.0 / d[i];
            let (ta, tb) = ((-half[i] - a[i]) * inv, (half[i] - a[i]) * inv);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
            if t0 > t1 {
                return None;
            }
        }
    }
    Some((t0, t1))
}

/// Box (A) – capsule (B): each segment end clipped to the reference face's sides and the
/// segment point nearest the box centre, as spheres against the box, and the segment's
/// deepest point where it lies deeper than those three (a capsule across an edge of the
/// box); the deepest point's normal is the manifold's.
#[allow(clippy::too_many_arguments)]
pub(crate) fn box_capsule(
    r: &M3,
    p: &V3,
    half: &V3,
    rc: &M3,
    pc: &V3,
    radius: f64,
    hh: f64,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    out.len = 0;
    let e = rc.column(2) * hh;
    let (s0, s1) = (pc - e, pc + e);
    // Every point within `radius + margin` of the box lies in the box grown by that much
    // along each of its axes: a segment that misses the grown box has no contact.
    let reach = radius + margin;
    let (a, b) = (r.tr_mul(&(s0 - p)), r.tr_mul(&(s1 - p)));
    let Some((t0, t1)) = (reach >= 0.0)
        .then(|| segment_in_box(&a, &b, &half.add_scalar(reach)))
        .flatten()
    else {
        return false;
    };
    // The deepest point is within reach only inside the grown box: search there.
    let deep = segment_deepest_in_box(&a, &b, t0, t1, half);
    let dist = box_signed_distance(&deep, half);
    // The segment's ends, each clipped to the side faces of the reference face (the box
    // face the deepest point leaves by, as a face–edge clip does): a capsule hanging over an
    // edge of that face keeps a point at the edge, so it cannot turn down over the edge
    // into the box within a step.
    let k = reference_axis(&deep, half);
    let mut sides = *half;
    sides[k] = f64::INFINITY;
    let (u0, u1) = segment_in_box(&a, &b, &sides).unwrap_or((0.0, 1.0));
    let at = |t: f64| s0 + (s1 - s0) * t;
    let ends = [
        if u0 > 0.0 { at(u0) } else { s0 },
        if u1 < 1.0 { at(u1) } else { s1 },
    ];
    let mid = segment_closest(&s0, &s1, p);
    let closest = [ends[0], ends[1], mid].map(|x| box_closest(r, p, half, &x));
    let nearest = closest.iter().fold(f64::INFINITY, |m, c| m.min(c.2));
    // A fourth point only where the segment lies deeper than the three by more than
    // round-off: where one of them is the deepest, the manifold stays theirs.
    let across = (dist < nearest - 1e-9 * (1.0 + nearest.abs()))
        .then(|| box_closest(r, p, half, &(p + r * deep)));
    let mut best = f64::INFINITY;
    for (q, n, dist) in closest.into_iter().chain(across) {
        let s = dist - radius;
        if s <= margin {
            if s < best {
                best = s;
                out.normal = n;
            }
            out.push(q + n * (0.5 * s), s);
        }
    }
    out.len > 0
}

/// Closest point of the solid cylinder `(r, p, radius, hh)` to `c`: (surface point, outward
/// normal, signed distance of `c`, negative inside), world frame.
pub(crate) fn cylinder_closest(r: &M3, p: &V3, radius: f64, hh: f64, c: &V3) -> (V3, V3, f64) {
    let cl = r.tr_mul(&(c - p));
    let rho = (cl.x * cl.x + cl.y * cl.y).sqrt();
    let radial = if rho > 1e-12 {
        V3::new(cl.x / rho, cl.y / rho, 0.0)
    } else {
        V3::x()
    };
    let inside = rho <= radius && cl.z.abs() <= hh;
    let (q, nl, dist) = if inside {
        let side = radius - rho;
        let cap = hh - cl.z.abs();
        if side < cap {
            (
                V3::new(radial.x * radius, radial.y * radius, cl.z),
                radial,
                -side,
            )
        } else {
            let sz = if cl.z >= 0.0 { 1.0 } else { -1.0 };
            (V3::new(cl.x, cl.y, sz * hh), V3::new(0.0, 0.0, sz), -cap)
        }
    } else {
        let rq = rho.min(radius);
        let q = V3::new(radial.x * rq, radial.y * rq, cl.z.clamp(-hh, hh));
        let diff = cl - q;
        let dn = diff.norm();
        (q, if dn > 1e-12 { diff / dn } else { radial }, dn)
    };
    (p + r * q, r * nl, dist)
}

/// Cylinder (A) – sphere (B): closest point of the solid cylinder to the centre.
#[allow(clippy::too_many_arguments)]
pub(crate) fn cylinder_sphere(
    r: &M3,
    p: &V3,
    radius: f64,
    hh: f64,
    c: &V3,
    rb: f64,
    margin: f64,
    out: &mut Manifold,
) -> bool {
    out.len = 0;
    let (q, n, dist) = cylinder_closest(r, p, radius, hh, c);
    let s = dist - rb;
    if s > margin {
        return false;
    }
    out.normal = n;
    out.push(q + n * (0.5 * s), s);
    true
}

/// A convex shape for the probing fallback: its closest-point query and its feature points.
pub(crate) enum Probe<'a> {
    /// Box `(r, p, half)`.
    Cuboid(&'a M3, &'a V3, &'a V3),
    /// Capsule `(r, p, radius, half_height)`.
    Capsule(&'a M3, &'a V3, f64, f64),
    /// Cylinder `(r, p, radius, half_height)`.
    Cylinder(&'a M3, &'a V3, f64, f64),
}

impl Probe<'_> {
    /// (surface point, outward normal, signed distance) for `x`.
    fn closest(&self, x: &V3) -> (V3, V3, f64) {
        match *self {
            Probe::Cuboid(r, p, half) => box_closest(r, p, half, x),
            Probe::Capsule(r, p, radius, hh) => {
                let e = r.column(2) * hh;
                let s = segment_closest(&(p - e), &(p + e), x);
                let d = x - s;
                let dn = d.norm();
                let n = if dn > 1e-12 {
                    d / dn
                } else {
                    r.column(0).into_owned()
                };
                (s + n * radius, n, dn - radius)
            }
            Probe::Cylinder(r, p, radius, hh) => cylinder_closest(r, p, radius, hh, x),
        }
    }

    /// Feature points with the radius that sweeps them: box corners and edge midpoints,
    /// capsule segment ends and middle, cylinder rim points.
    fn points(&self, out: &mut [(V3, f64); 24]) -> usize {
        match *self {
            Probe::Cuboid(r, p, half) => {
                let mut n = 0;
                for k in 0..27 {
                    let s = [k % 3, (k / 3) % 3, k / 9].map(|v| v as f64 - 1.0);
                    let zeros = s.iter().filter(|v| **v == 0.0).count();
                    if zeros <= 1 {
                        let l = V3::new(s[0] * half.x, s[1] * half.y, s[2] * half.z);
                        out[n] = (p + r * l, 0.0);
                        n += 1;
                    }
                }
                n
            }
            Probe::Capsule(r, p, radius, hh) => {
                let e = r.column(2) * hh;
                out[0] = (p - e, radius);
                out[1] = (*p, radius);
                out[2] = (p + e, radius);
                3
            }
            Probe::Cylinder(r, p, radius, hh) => {
                let (ex, ey, ez) = (r.column(0), r.column(1), r.column(2));
                for k in 0..8 {
                    let t = k as f64 * std::f64::consts::FRAC_PI_4;
                    let (s, c) = crate::transcendental::sin_cos(t);
                    let rim = (ex * c + ey * s) * radius;
                    out[3 * k] = (p + rim + ez * hh, 0.0);
                    out[3 * k + 1] = (p + rim - ez * hh, 0.0);
                    out[3 * k + 2] = (p + rim, 0.0);
                }
                24
            }
        }
    }
}

/// Probing fallback for the pairs without a closed form (cylinder against box, capsule or
/// cylinder): each shape's feature points against the other's closest-point query; the
/// deepest probe gives the normal (A to B), probes agreeing with it (within ~25°) give up to
/// 4 points. Approximate: exact for the resting and face cases, it can miss the deepest
/// point of an edge crossing a cylinder side between probes.
pub(crate) fn probe_pair(a: &Probe, b: &Probe, margin: f64, out: &mut Manifold) -> bool {
    out.len = 0;
    let mut cand = [(V3::zeros(), V3::zeros(), 0.0); 48];
    let mut m = 0;
    let mut pts = [(V3::zeros(), 0.0); 24];
    // A's points against B: normal A→B is −n_B.
    let k = a.points(&mut pts);
    for &(x, rad) in &pts[..k] {
        let (q, n, d) = b.closest(&x);
        let s = d - rad;
        if s <= margin {
            cand[m] = ((x - n * rad + q) * 0.5, -n, s);
            m += 1;
        }
    }
    let k = b.points(&mut pts);
    for &(y, rad) in &pts[..k] {
        let (q, n, d) = a.closest(&y);
        let s = d - rad;
        if s <= margin {
            cand[m] = ((y - n * rad + q) * 0.5, n, s);
            m += 1;
        }
    }
    if m == 0 {
        return false;
    }
    cand[..m].sort_by(|u, v| u.2.total_cmp(&v.2));
    let n = cand[0].1;
    out.normal = n;
    for c in &cand[..m] {
        if c.1.dot(&n) > 0.9 {
            out.push(c.0, c.2);
        }
    }
    true
}
