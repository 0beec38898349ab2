//! What a contact gives at rest under a column of bodies: the tilt its load's offset
//! makes, its stiffness against rocking, the overlap it settles at. The resting-column
//! analysis reads these (`pipeline/island_substeps.rs`, `pipeline/resting_substeps.rs`).

use super::{tangent_basis, ContactConstraint, PointConstraint, TILT_MIN_SPAN};
use crate::geometry::V3;

impl ContactConstraint {
    /// The tilt (rad) this contact takes at rest under a column of weight `weight` (N) whose
    /// centre of mass is at `com` (m, world); `origin_a` is body A's centre of mass (m, world),
    /// `up` the unit vector against gravity and `omega` the normal rows' stiffness (rad/s).
    ///
    /// Where the weight's line falls within the middle third of the contact (seen from the
    /// points' centroid towards it), every point stays loaded and the contact has no tilt to
    /// give. Beyond, the far side lifts and the points on the near side carry the whole
    /// weight, each row a spring of its effective mass, `m ω²`: they sink
    /// `weight / Σ m ω²`, and the body above tilts by that sink over the contact's width
    /// along the offset. Where the line falls beyond the outermost point the column tips over
    /// whatever the stiffness: no tilt at rest (0).
    pub(crate) fn column_tilt(
        &self,
        origin_a: &V3,
        com: &V3,
        weight: f64,
        up: &V3,
        omega: f64,
    ) -> f64 {
        let points = &self.points[..self.len];
        if points.len() < 2 {
            return 0.0;
        }
        let flat = |v: V3| v - up * up.dot(&v);
        let centroid = points.iter().map(|p| p.ra).sum::<V3>() / points.len() as f64 + origin_a;
        let offset = flat(com - centroid);
        let e = offset.norm();
        if e.is_nan() || e <= 0.0 {
            return 0.0;
        }
        let d = offset / e;
        let along = |p: &PointConstraint| d.dot(&flat(origin_a + p.ra - centroid));
        let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut stiffness = 0.0;
        for p in points {
            let s = along(p);
            near = near.max(s);
            far = far.min(s);
            if s > 0.0 {
                stiffness += p.n.mass * omega * omega;
            }
        }
        let span = near - far;
        let lifts =
            near > 0.0 && e > near / 3.0 && e < near && span >= TILT_MIN_SPAN && stiffness > 0.0;
        if !lifts {
            return 0.0;
        }
        weight / stiffness / span
    }

    /// The contact's stiffness against tilting (N·m/rad) at stiffness `omega` (rad/s): its
    /// normal rows, each a spring of its effective mass `m ω²`, resist a turn of the body on
    /// top about the points' centroid by `Σ m ω² s sᵀ`, `s` each point's offset from the
    /// centroid across `up`; the least of that in the plane across `up`. Zero for a contact on
    /// one point or along a line, which holds no column upright.
    pub(crate) fn rocking_stiffness(&self, up: &V3, omega: f64) -> f64 {
        let points = &self.points[..self.len];
        if points.len() < 3 {
            return 0.0;
        }
        let [e1, e2] = tangent_basis(up);
        let centroid = points.iter().map(|p| p.ra).sum::<V3>() / points.len() as f64;
        let (mut a, mut b, mut d) = (0.0, 0.0, 0.0);
        for p in points {
            let s = p.ra - centroid;
            let (x, y) = (s.dot(&e1), s.dot(&e2));
            let k = p.n.mass * omega * omega;
            a += k * x * x;
            b += k * x * y;
            d += k * y * y;
        }
        let least = 0.5 * (a + d) - (0.25 * (a - d) * (a - d) + b * b).sqrt();
        if least.is_finite() {
            least.max(0.0)
        } else {
            0.0
        }
    }

    /// The overlap (m) at which this contact's most loaded point settles under the load it
    /// carried, at stiffness `omega` (rad/s): its carried normal impulse `λ`, accumulated over
    /// the manifold's `impulse_substep` (s), is the force `λ / h`, and a soft row of effective
    /// mass `m` at rest under a force `F` overlaps by `F / (m ω²)` (see [`Softness::new`]).
    pub(crate) fn resting_overlap(&self, omega: f64) -> f64 {
        let h = self.impulse_substep;
        if h <= 0.0 || omega <= 0.0 {
            return 0.0;
        }
        self.points[..self.len]
            .iter()
            .filter(|p| p.n.mass > 0.0 && p.normal_impulse > 0.0)
            .map(|p| p.normal_impulse / h / (p.n.mass * omega * omega))
            .fold(0.0, f64::max)
    }

    /// The overlap (m) at which this contact's points settle under the loads they carried,
    /// at stiffness `omega` (rad/s), on the mean over its points (an unloaded point at none):
    /// [`ContactConstraint::resting_overlap`]'s overlap, point by point.
    pub(crate) fn mean_resting_overlap(&self, omega: f64) -> f64 {
        let h = self.impulse_substep;
        if h <= 0.0 || omega <= 0.0 || self.len == 0 {
            return 0.0;
        }
        self.points[..self.len]
            .iter()
            .filter(|p| p.n.mass > 0.0 && p.normal_impulse > 0.0)
            .map(|p| p.normal_impulse / h / (p.n.mass * omega * omega))
            .sum::<f64>()
            / self.len as f64
    }
}

#[cfg(test)]
mod tests {
    use super::super::{ContactConstraint, ContactSettings};
    use crate::dynamics::BodySet;
    use crate::dynamics::{BodyKind, Material};
    use crate::geometry::{Manifold, Shape, M3, V3};

    /// Two unit boxes of 1 kg, B on A, with a face contact at the four corners of `z = 1`.
    fn box_on_box() -> (BodySet, ContactConstraint) {
        let mut b = BodySet::default();
        for z in [0.5, 1.5] {
            b.push(
                String::new(),
                BodyKind::Dynamic,
                Shape::Cuboid {
                    half: V3::new(0.5, 0.5, 0.5),
                },
                Material::default(),
                1.0,
                V3::new(0.0, 0.0, z),
                M3::identity(),
                V3::zeros(),
                V3::zeros(),
            );
        }
        b.update_world_inertia();
        let mut m = Manifold::new(0, 1);
        m.normal = V3::z();
        for (x, y) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            m.push(V3::new(x, y, 1.0), 0.0);
        }
        let c = ContactConstraint::prepare(&b, &m, 0, &ContactSettings::default());
        (b, c)
    }

    #[test]
    fn a_column_tilts_its_contact_only_beyond_the_middle_third() {
        let (b, c) = box_on_box();
        let (origin, up, weight) = (b.pos[0], V3::z(), 24.0 * 9.81);
        let omega = 2.0 * std::f64::consts::PI * 180.0;
        // Within the middle third (a sixth of the width from the centre): no tilt.
        for x in [0.0, 0.1, -0.16] {
            let com = V3::new(x, 0.0, 13.0);
            assert_eq!(
                c.column_tilt(&origin, &com, weight, &up, omega),
                0.0,
                "x = {x}"
            );
        }
        // Beyond it the two points on the near side carry the weight as springs of their
        // rows' effective masses, and the contact tilts by their sink over its 1 m width.
        let near: f64 = c.points[..c.len]
            .iter()
            .filter(|p| p.ra.x > 0.0)
            .map(|p| p.n.mass)
            .sum();
        let expected = weight / (near * omega * omega) / 1.0;
        let tilt = c.column_tilt(&origin, &V3::new(0.3, 0.0, 13.0), weight, &up, omega);
        assert!(
            (tilt - expected).abs() <= 1e-12 * expected,
            "{tilt} {expected}"
        );
        // The tilt is the same whichever way the offset points, and twice the weight tilts
        // twice as much.
        let other = c.column_tilt(&origin, &V3::new(0.0, -0.3, 13.0), weight, &up, omega);
        assert!(
            (other - expected).abs() <= 1e-9 * expected,
            "{other} {expected}"
        );
        let double = c.column_tilt(&origin, &V3::new(0.3, 0.0, 13.0), 2.0 * weight, &up, omega);
        assert!((double - 2.0 * expected).abs() <= 1e-12 * expected);
    }

    #[test]
    fn a_column_whose_centre_of_mass_falls_beyond_its_contact_predicts_no_tilt() {
        let (b, c) = box_on_box();
        let (origin, up, weight) = (b.pos[0], V3::z(), 24.0 * 9.81);
        let omega = 2.0 * std::f64::consts::PI * 180.0;
        // The contact's points lie 0.5 m from its centroid along x: just inside, the near
        // edge carries the column; beyond, the column tips over whatever the stiffness.
        let inside = c.column_tilt(&origin, &V3::new(0.49, 0.0, 13.0), weight, &up, omega);
        assert!(inside > 0.0, "{inside}");
        for x in [0.5, 0.51, 2.0, -0.7] {
            let com = V3::new(x, 0.0, 13.0);
            assert_eq!(
                c.column_tilt(&origin, &com, weight, &up, omega),
                0.0,
                "x = {x}"
            );
        }
    }
}
