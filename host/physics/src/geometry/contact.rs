//! Contact points and manifolds.

use super::{PairPose, V3};

/// Most points a manifold keeps (a face–face box contact reduces to 4).
pub const MAX_MANIFOLD_POINTS: usize = 4;

/// One contact point (world frame).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactPoint {
    /// Midpoint between the two surfaces (m, world).
    pub point: V3,
    /// Signed distance along the normal, negative when overlapping (m).
    pub separation: f64,
    /// Anchor in body A's frame (m), used to match points across steps.
    pub(crate) local_a: V3,
    /// Anchor in body B's frame (m) when the manifold was collided (for a refresh).
    pub(crate) local_b: V3,
    /// Separation when the manifold was collided (m).
    pub(crate) origin_separation: f64,
    /// Accumulated normal impulse (N·s), carried over for warm starting.
    pub(crate) normal_impulse: f64,
    /// Accumulated tangent impulses along the manifold's two tangents (N·s), for a contact
    /// solved point by point (an articulated link's); a free body's contact carries its
    /// friction for the whole manifold ([`Manifold::friction_impulse`]).
    pub(crate) tangent_impulse: [f64; 2],
    /// Largest normal impulse applied in the last step (N·s): the contact's "hit" strength.
    pub(crate) max_normal_impulse: f64,
}

/// The contact between a shape of one body and a shape of another: a shared normal and up to
/// four points. A pair of compound bodies has one manifold per pair of touching parts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Manifold {
    /// Body A (index into the body set); the normal points from A to B.
    pub(crate) a: u32,
    /// Body B.
    pub(crate) b: u32,
    /// Part of A's shape that touches (0 unless A is a compound).
    pub(crate) part_a: u16,
    /// Part of B's shape that touches (0 unless B is a compound).
    pub(crate) part_b: u16,
    /// Unit normal, world frame, from A to B.
    pub normal: V3,
    /// Points (first `len` valid).
    pub(crate) points: [ContactPoint; MAX_MANIFOLD_POINTS],
    /// Number of valid points.
    pub(crate) len: usize,
    /// Accumulated friction impulse at the points' centroid along the manifold's two
    /// tangents (N·s), warm started (patch friction).
    pub(crate) friction_impulse: [f64; 2],
    /// Accumulated torsional friction impulse about the normal (N·m·s), warm started.
    pub(crate) twist_impulse: f64,
    /// Accumulated rolling-resistance angular impulse (N·m·s, world), warm started.
    pub(crate) rolling_impulse: V3,
    /// The substep (s) over which the carried impulses were accumulated (they are per
    /// substep); 0 when none were.
    pub(crate) impulse_substep: f64,
    /// Overlap (m) each point is solved as if it had beyond its own: the sink the contact's
    /// load leaves in a soft contact, learned step after step, so a resting stack stands at
    /// its slop instead of sinking (`pipeline/sink_hold.rs`).
    pub(crate) held_overlap: f64,
    /// Where B lay in A's frame when the points were collided; `None` for a manifold that is
    /// always collided again (compounds, round shapes, continuous collision).
    pub(crate) origin: Option<PairPose>,
}

impl Manifold {
    /// An empty manifold between `a` and `b` (their first parts).
    pub fn new(a: u32, b: u32) -> Self {
        Self::between_parts(a, 0, b, 0)
    }

    /// An empty manifold between part `part_a` of body `a` and part `part_b` of body `b`.
    pub(crate) fn between_parts(a: u32, part_a: u16, b: u32, part_b: u16) -> Self {
        Self {
            a,
            b,
            part_a,
            part_b,
            normal: V3::z(),
            points: [ContactPoint::default(); MAX_MANIFOLD_POINTS],
            len: 0,
            friction_impulse: [0.0; 2],
            twist_impulse: 0.0,
            rolling_impulse: V3::zeros(),
            impulse_substep: 0.0,
            held_overlap: 0.0,
            origin: None,
        }
    }

    /// The sorted pair key `a << 32 | b`.
    #[inline]
    pub(crate) fn key(&self) -> u64 {
        ((self.a as u64) << 32) | self.b as u64
    }

    /// The sort key of the manifold among those of its body pair: `part_a << 16 | part_b`.
    #[inline]
    pub(crate) fn part_key(&self) -> u32 {
        ((self.part_a as u32) << 16) | self.part_b as u32
    }

    /// The valid points.
    pub fn points(&self) -> &[ContactPoint] {
        &self.points[..self.len]
    }

    /// Appends a point (ignored when full).
    #[inline]
    pub(crate) fn push(&mut self, point: V3, separation: f64) {
        if self.len < MAX_MANIFOLD_POINTS {
            self.points[self.len] = ContactPoint {
                point,
                separation,
                ..Default::default()
            };
            self.len += 1;
        }
    }

    /// Deepest separation of the valid points (m), `+∞` when empty.
    pub(crate) fn min_separation(&self) -> f64 {
        self.points()
            .iter()
            .map(|p| p.separation)
            .fold(f64::INFINITY, f64::min)
    }
}
