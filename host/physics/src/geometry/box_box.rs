//! Box–box contact: separating-axis test over the 15 candidate axes, then either face
//! clipping (the incident face clipped by the reference face's side planes, up to 8 points
//! reduced to 4) or one edge–edge point.
//!
//! A dedicated path rather than a general convex–convex routine because stacks of boxes are
//! the engine's demanding case (`towers-1120`, `pyramid-1240`): the clipped face gives the 4
//! stable corner points that keep stacks from rocking, at the cost of a few hundred flops.

use super::{Manifold, M3, V3};

/// How much better (m) a B face or an edge axis must separate than the best A face to be
/// chosen (hysteresis keeps resting contacts on stable face features).
const FEATURE_TOLERANCE: f64 = 1e-3;

/// A box pose and half extents.
#[derive(Clone, Copy, Debug)]
pub struct BoxPose<'a> {
    /// World from body rotation (columns are the box axes).
    pub r: &'a M3,
    /// Centre (m, world).
    pub p: &'a V3,
    /// Half extents (m).
    pub half: &'a V3,
}

#[inline]
fn projected_radius(b: &BoxPose, axis: &V3) -> f64 {
    b.half.x * b.r.column(0).dot(axis).abs()
        + b.half.y * b.r.column(1).dot(axis).abs()
        + b.half.z * b.r.column(2).dot(axis).abs()
}

/// Fills `out` (normal from `a` to `b`, points with separations) when the boxes are closer
/// than `margin` (m). Returns whether any point was produced.
pub fn box_box(a: BoxPose, b: BoxPose, margin: f64, out: &mut Manifold) -> bool {
    out.len = 0;
    let d = b.p - a.p;
    // Face axes of A and B.
    let mut best_a = (f64::NEG_INFINITY, 0usize);
    for i in 0..3 {
        let ax = a.r.column(i).into_owned();
        let s = d.dot(&ax).abs() - a.half[i] - projected_radius(&b, &ax);
        if s > margin {
            return false;
        }
        if s > best_a.0 {
            best_a = (s, i);
        }
    }
    let mut best_b = (f64::NEG_INFINITY, 0usize);
    for j in 0..3 {
        let ax = b.r.column(j).into_owned();
        let s = d.dot(&ax).abs() - b.half[j] - projected_radius(&a, &ax);
        if s > margin {
            return false;
        }
        if s > best_b.0 {
            best_b = (s, j);
        }
    }
    // Edge axes.
    let mut best_e = (f64::NEG_INFINITY, 0usize, 0usize, V3::zeros());
    for i in 0..3 {
        for j in 0..3 {
            let c = a.r.column(i).cross(&b.r.column(j));
            let n2 = c.norm_squared();
            if n2 < 1e-10 {
                continue;
            }
            let ax = c / n2.sqrt();
            let s = d.dot(&ax).abs() - projected_radius(&a, &ax) - projected_radius(&b, &ax);
            if s > margin {
                return false;
            }
            if s > best_e.0 {
                best_e = (s, i, j, ax);
            }
        }
    }
    let face_best = best_a.0.max(best_b.0);
    if best_e.0 > face_best + FEATURE_TOLERANCE {
        edge_contact(a, b, best_e.1, best_e.2, best_e.3, d, out);
    } else if best_b.0 > best_a.0 + FEATURE_TOLERANCE {
        face_contact(b, a, best_b.1, -d, margin, out);
        out.normal = -out.normal;
    } else {
        face_contact(a, b, best_a.1, d, margin, out);
    }
    out.len > 0
}

/// One point between the supporting edges of `a` (axis `i`) and `b` (axis `j`).
fn edge_contact(a: BoxPose, b: BoxPose, i: usize, j: usize, axis: V3, d: V3, out: &mut Manifold) {
    let n = if axis.dot(&d) < 0.0 { -axis } else { axis };
    let mut pa = *a.p;
    let mut pb = *b.p;
    for k in 0..3 {
        if k != i {
            let c = a.r.column(k);
            pa += c * (a.half[k] * c.dot(&n).signum());
        }
        if k != j {
            let c = b.r.column(k);
            pb -= c * (b.half[k] * c.dot(&n).signum());
        }
    }
    let ea = a.r.column(i).into_owned();
    let eb = b.r.column(j).into_owned();
    // Closest points of the two segments pa + s ea, pb + t eb, |s| ≤ ha_i, |t| ≤ hb_j.
    let r = pa - pb;
    let (aa, bb, ab) = (1.0, 1.0, ea.dot(&eb));
    let (c1, f) = (ea.dot(&r), eb.dot(&r));
    let den = aa * bb - ab * ab;
    let mut s = if den > 1e-12 {
        ((ab * f - c1 * bb) / den).clamp(-a.half[i], a.half[i])
    } else {
        0.0
    };
    let t = ((ab * s + f) / bb).clamp(-b.half[j], b.half[j]);
    s = ((ab * t - c1) / aa).clamp(-a.half[i], a.half[i]);
    let qa = pa + ea * s;
    let qb = pb + eb * t;
    out.normal = n;
    out.push((qa + qb) * 0.5, (qb - qa).dot(&n));
}

/// Clips the face of `inc` most opposed to reference face `i` of `rf` (normal towards `d`).
fn face_contact(rf: BoxPose, inc: BoxPose, i: usize, d: V3, margin: f64, out: &mut Manifold) {
    let ax = rf.r.column(i).into_owned();
    let n = if ax.dot(&d) < 0.0 { -ax } else { ax };
    // Incident face: the inc face whose normal is most anti-parallel to n.
    let mut j = 0;
    let mut best = -1.0;
    for k in 0..3 {
        let v = inc.r.column(k).dot(&n).abs();
        if v > best {
            best = v;
            j = k;
        }
    }
    let cj = inc.r.column(j).into_owned();
    let sign = if cj.dot(&n) > 0.0 { -1.0 } else { 1.0 };
    let fc = inc.p + cj * (sign * inc.half[j]);
    let (u, v) = ((j + 1) % 3, (j + 2) % 3);
    let eu = inc.r.column(u) * inc.half[u];
    let ev = inc.r.column(v) * inc.half[v];
    let mut poly = [V3::zeros(); 8];
    let mut tmp = [V3::zeros(); 8];
    poly[0] = fc + eu + ev;
    poly[1] = fc - eu + ev;
    poly[2] = fc - eu - ev;
    poly[3] = fc + eu - ev;
    let mut len = 4;
    // Side planes of the reference face.
    for k in [(i + 1) % 3, (i + 2) % 3] {
        let c = rf.r.column(k).into_owned();
        let o = c.dot(rf.p);
        len = clip(&poly, len, &c, o + rf.half[k], &mut tmp);
        std::mem::swap(&mut poly, &mut tmp);
        len = clip(&poly, len, &(-c), -(o - rf.half[k]), &mut tmp);
        std::mem::swap(&mut poly, &mut tmp);
        if len == 0 {
            return;
        }
    }
    let face_offset = n.dot(rf.p) + rf.half[i];
    out.normal = n;
    let mut pts = [(V3::zeros(), 0.0); 8];
    let mut m = 0;
    for q in &poly[..len] {
        let s = n.dot(q) - face_offset;
        if s <= margin {
            pts[m] = (q - n * (0.5 * s), s);
            m += 1;
        }
    }
    reduce(&pts[..m], &n, out);
}

/// Sutherland–Hodgman: keeps the part of `inp` with `n·x ≤ o`.
fn clip(inp: &[V3; 8], len: usize, n: &V3, o: f64, out: &mut [V3; 8]) -> usize {
    let mut m = 0;
    for k in 0..len {
        let p = inp[k];
        let q = inp[(k + 1) % len];
        let (dp, dq) = (n.dot(&p) - o, n.dot(&q) - o);
        if dp <= 0.0 && m < 8 {
            out[m] = p;
            m += 1;
        }
        if (dp <= 0.0) != (dq <= 0.0) && m < 8 {
            let t = dp / (dp - dq);
            out[m] = p + (q - p) * t;
            m += 1;
        }
    }
    m
}

/// Keeps at most 4 points: the deepest, the farthest from it, then the two that add the most
/// area on either side of their line.
fn reduce(pts: &[(V3, f64)], n: &V3, out: &mut Manifold) {
    if pts.len() <= 4 {
        for (p, s) in pts {
            out.push(*p, *s);
        }
        return;
    }
    let mut i0 = 0;
    for (k, p) in pts.iter().enumerate() {
        if p.1 < pts[i0].1 {
            i0 = k;
        }
    }
    let mut i1 = 0;
    let mut best = -1.0;
    for (k, p) in pts.iter().enumerate() {
        let dd = (p.0 - pts[i0].0).norm_squared();
        if dd > best {
            best = dd;
            i1 = k;
        }
    }
    let (mut i2, mut i3) = (usize::MAX, usize::MAX);
    let (mut amax, mut amin) = (0.0, 0.0);
    let e = pts[i1].0 - pts[i0].0;
    for (k, p) in pts.iter().enumerate() {
        let a = e.cross(&(p.0 - pts[i0].0)).dot(n);
        if a > amax {
            amax = a;
            i2 = k;
        }
        if a < amin {
            amin = a;
            i3 = k;
        }
    }
    for k in [i0, i1, i2, i3] {
        if k != usize::MAX {
            out.push(pts[k].0, pts[k].1);
        }
    }
}
