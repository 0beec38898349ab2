//! The joints' constraint blocks solved together and exactly, when the joints between moving
//! bodies form a forest: a sparse factorisation of the saddle-point system in linear time
//! (Baraff, "Linear-time dynamics using Lagrange multipliers", SIGGRAPH 1996).
//!
//! Solved one joint after another (Gauss–Seidel), a chain whose links differ in mass by 1:100
//! opens: the light link's correction is undone by its heavy neighbour, and one pass per
//! substep converges too slowly. Solving every joint at once finds the impulses `Δλ` that set
//! all the rows' rates together,
//!
//! ```text
//! [ M  Jᵀ ] [ Δv ]   [  0 ]
//! [ J  0  ] [ μ  ] = [ −b ],   Δλ = −μ = −(J M⁻¹ Jᵀ)⁻¹ b,
//! ```
//!
//! with `M` the moving bodies' masses and inertias (world axes), `J` the joints' rows and `b`
//! each row's rate plus its soft position bias. The nodes of this system are the moving
//! bodies and the joints, and its edges are the Jacobian blocks; when that graph is a forest,
//! eliminating every node after its children fills in nothing, so the factorisation and
//! each solve cost `O(n)` 6 × 6 blocks. The soft coefficients apply to the whole block as
//! they do to one joint (`Δλ = −s_m (J M⁻¹ Jᵀ)⁻¹ b − s_i λ`): without shared bodies the
//! result is the joint-by-joint solve's.
//!
//! Joints that close a loop among moving bodies leave the system without that structure;
//! the solver then keeps the joint-by-joint passes.

use super::joint_constraint::FreeJoint;
use super::Softness;
use crate::dynamics::BodySet;

type M6 = nalgebra::Matrix6<f64>;
type V6 = nalgebra::Vector6<f64>;

/// The joints' soft coefficients for one substep.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JointSoftness {
    /// For joints solved one after another (the `joint_hertz` setting).
    pub(crate) each: Softness,
    /// For a forest solved as one system: [`Self::forest`].
    pub(crate) forest: Softness,
}

impl JointSoftness {
    /// A forest's coefficients over a substep of `h` seconds. Solved exactly, its rows need
    /// no softening against each other, so the position error is corrected as stiffly as a
    /// soft constraint integrated over `h` stays accurate (`hertz = 1 / (4 h)`), critically damped
    /// (figures in `docs/physics/integrators-accuracy-hard-cases.md`, "Joint forests solved as one system").
    pub(crate) fn forest(h: f64) -> Softness {
        Softness::new(0.25 / h, 1.0, h)
    }
}

/// What a node of the system stands for.
#[derive(Clone, Copy, Debug)]
enum NodeKind {
    /// A moving body (storage index).
    Body(usize),
    /// A joint (index into the world's joints).
    Joint(usize),
}

/// A node: what it is, its parent in the forest (a node index) and the block `H_{c,p}`
/// coupling it to the parent (a joint's rows against the body's velocity `(v, ω)`, or the
/// transpose for a body under a joint).
#[derive(Clone, Copy, Debug)]
struct Node {
    kind: NodeKind,
    parent: Option<usize>,
    coupling: M6,
}

/// The forest of moving bodies and joints, its factorisation for the current substep, and
/// the scratch of one solve.
#[derive(Clone, Debug, Default)]
pub(crate) struct JointGraph {
    /// Nodes in elimination order: every node before its parent.
    nodes: Vec<Node>,
    /// Whether the joints form a forest (and the factorisation succeeded).
    usable: bool,
    /// `D⁻¹` of each node's pivot block.
    pivot_inv: Vec<M6>,
    /// Each joint's node (or `usize::MAX`: no rows or no moving body).
    joint_node: Vec<usize>,
    /// Each body's node (or `usize::MAX`).
    body_node: Vec<usize>,
    /// Joints at each body: offsets into `incident`, and the joint indices.
    incident_start: Vec<usize>,
    incident: Vec<usize>,
    /// Breadth-first queue of node indices (scratch).
    queue: Vec<usize>,
    /// Fill positions while sorting, then the new number of each node (scratch).
    fill: Vec<usize>,
    /// The nodes while they are put in elimination order (scratch).
    ordered: Vec<Node>,
    /// Right-hand side, then solution, per node (scratch).
    work: Vec<V6>,
    /// Each joint's right-hand side, then its `μ` (scratch).
    rhs: Vec<V6>,
}

/// Marks a body or joint without a node.
const NONE: usize = usize::MAX;

/// Whether body `i` moves in the joints' solve (dynamic and awake).
fn moving(bodies: &BodySet, i: usize) -> bool {
    bodies.awake[i] && bodies.inv_mass[i] > 0.0
}

impl JointGraph {
    /// Whether the last [`Self::build`] and [`Self::factor`] left a forest to solve.
    pub(crate) fn usable(&self) -> bool {
        self.usable
    }

    /// Finds the forest of moving bodies and `joints` (whose rows are current); `usable`
    /// is false when the joints close a loop among moving bodies.
    pub(crate) fn build(&mut self, joints: &[FreeJoint], bodies: &BodySet) {
        let nb = bodies.len();
        self.nodes.clear();
        self.joint_node.clear();
        self.joint_node.resize(joints.len(), NONE);
        self.body_node.clear();
        self.body_node.resize(nb, NONE);
        self.index_incident(joints, bodies);
        let active = |j: &FreeJoint| j.row_count() > 0;
        // Breadth first from each unvisited joint, parents visited before children. A joint
        // to a body that does not move must be a root: as a leaf its pivot would be its zero
        // block. So the roots are those joints first, then any joint of what is left.
        self.queue.clear();
        let anchored = |k: usize| {
            let (a, b) = joints[k].bodies();
            moving(bodies, a) != moving(bodies, b)
        };
        for start in (0..joints.len())
            .filter(|&k| anchored(k))
            .chain(0..joints.len())
        {
            if self.joint_node[start] != NONE || !active(&joints[start]) {
                continue;
            }
            let (a, b) = joints[start].bodies();
            if !moving(bodies, a) && !moving(bodies, b) {
                continue;
            }
            self.joint_node[start] = self.push(NodeKind::Joint(start), None);
            let mut head = self.queue.len();
            self.queue.push(self.joint_node[start]);
            while head < self.queue.len() {
                let n = self.queue[head];
                head += 1;
                let parent = self.nodes[n].parent;
                match self.nodes[n].kind {
                    NodeKind::Joint(k) => {
                        let (a, b) = joints[k].bodies();
                        let children = [a, b]
                            .iter()
                            .filter(|&&i| {
                                moving(bodies, i) && !parent.is_some_and(|p| self.is_body(p, i))
                            })
                            .count();
                        if children == 0 {
                            // A second joint to the still world closes a loop through it.
                            self.usable = false;
                            return;
                        }
                        for i in [a, b] {
                            if !moving(bodies, i) || parent.is_some_and(|p| self.is_body(p, i)) {
                                continue;
                            }
                            if self.body_node[i] != NONE {
                                self.usable = false; // a loop
                                return;
                            }
                            self.body_node[i] = self.push(NodeKind::Body(i), Some(n));
                            self.queue.push(self.body_node[i]);
                        }
                    }
                    NodeKind::Body(i) => {
                        for s in self.incident_start[i]..self.incident_start[i + 1] {
                            let k = self.incident[s];
                            if parent.is_some_and(|p| self.is_joint(p, k)) {
                                continue;
                            }
                            if self.joint_node[k] != NONE {
                                self.usable = false; // a loop
                                return;
                            }
                            self.joint_node[k] = self.push(NodeKind::Joint(k), Some(n));
                            self.queue.push(self.joint_node[k]);
                        }
                    }
                }
            }
        }
        self.order_for_elimination();
        self.usable = true;
    }

    /// The joints at each moving body (`incident`, from `incident_start`): a counting sort
    /// by body of the joints with rows.
    fn index_incident(&mut self, joints: &[FreeJoint], bodies: &BodySet) {
        let nb = bodies.len();
        // Joints at each body, counting sort by body.
        self.incident_start.clear();
        self.incident_start.resize(nb + 1, 0);
        let active = |j: &FreeJoint| j.row_count() > 0;
        for j in joints.iter().filter(|j| active(j)) {
            let (a, b) = j.bodies();
            for i in [a, b] {
                if moving(bodies, i) {
                    self.incident_start[i + 1] += 1;
                }
            }
        }
        for i in 0..nb {
            self.incident_start[i + 1] += self.incident_start[i];
        }
        self.incident.clear();
        self.incident.resize(self.incident_start[nb], 0);
        self.fill.clear();
        self.fill.extend_from_slice(&self.incident_start);
        for (k, j) in joints.iter().enumerate().filter(|(_, j)| active(j)) {
            let (a, b) = j.bodies();
            for i in [a, b] {
                if moving(bodies, i) {
                    self.incident[self.fill[i]] = k;
                    self.fill[i] += 1;
                }
            }
        }
    }

    /// The nodes renumbered in elimination order, the reverse of the breadth-first order,
    /// with their parents and the joints' and bodies' nodes.
    fn order_for_elimination(&mut self) {
        // Elimination order: the reverse of the breadth-first order.
        let n = self.nodes.len();
        self.fill.clear();
        self.fill.resize(n, NONE);
        for (new, &old) in self.queue.iter().rev().enumerate() {
            self.fill[old] = new;
        }
        self.ordered.clear();
        for &old in self.queue.iter().rev() {
            let mut node = self.nodes[old];
            node.parent = node.parent.map(|p| self.fill[p]);
            self.ordered.push(node);
        }
        std::mem::swap(&mut self.nodes, &mut self.ordered);
        for x in self.joint_node.iter_mut().chain(self.body_node.iter_mut()) {
            if *x != NONE {
                *x = self.fill[*x];
            }
        }
    }

    fn push(&mut self, kind: NodeKind, parent: Option<usize>) -> usize {
        self.nodes.push(Node {
            kind,
            parent,
            coupling: M6::zeros(),
        });
        self.nodes.len() - 1
    }

    fn is_body(&self, node: usize, i: usize) -> bool {
        matches!(self.nodes[node].kind, NodeKind::Body(b) if b == i)
    }

    fn is_joint(&self, node: usize, k: usize) -> bool {
        matches!(self.nodes[node].kind, NodeKind::Joint(j) if j == k)
    }

    /// Factorises the system for the joints' current rows and the bodies' masses; leaves
    /// the graph unusable if a pivot block is singular.
    pub(crate) fn factor(&mut self, joints: &[FreeJoint], bodies: &BodySet) {
        if !self.usable {
            return;
        }
        let n = self.nodes.len();
        self.pivot_inv.clear();
        self.pivot_inv.resize(n, M6::zeros());
        // Pivot blocks start as the diagonal of H: a body's mass matrix, a joint's zero block
        // (its unused rows −1 so that they stay decoupled).
        for c in 0..n {
            let node = self.nodes[c];
            let (diag, coupling) = match node.kind {
                NodeKind::Body(i) => {
                    let Some(inertia) = bodies.inv_inertia_world[i].try_inverse() else {
                        self.usable = false;
                        return;
                    };
                    let mut m = M6::zeros();
                    let mass = 1.0 / bodies.inv_mass[i];
                    for d in 0..3 {
                        m[(d, d)] = mass;
                    }
                    m.fixed_view_mut::<3, 3>(3, 3).copy_from(&inertia);
                    let coupling = match node.parent.map(|p| self.nodes[p].kind) {
                        Some(NodeKind::Joint(k)) => joints[k].jacobian(i).transpose(),
                        _ => M6::zeros(),
                    };
                    (m, coupling)
                }
                NodeKind::Joint(k) => {
                    let mut z = M6::zeros();
                    for d in joints[k].row_count()..6 {
                        z[(d, d)] = -1.0;
                    }
                    let coupling = match node.parent.map(|p| self.nodes[p].kind) {
                        Some(NodeKind::Body(i)) => joints[k].jacobian(i),
                        _ => M6::zeros(),
                    };
                    (z, coupling)
                }
            };
            self.nodes[c].coupling = coupling;
            self.pivot_inv[c] = diag;
        }
        for c in 0..n {
            let Some(inv) = self.pivot_inv[c].try_inverse() else {
                self.usable = false;
                return;
            };
            self.pivot_inv[c] = inv;
            if let Some(p) = self.nodes[c].parent {
                let e = &self.nodes[c].coupling;
                let update = e.transpose() * inv * e;
                self.pivot_inv[p] -= update;
            }
        }
    }

    /// One pass over every joint's constraint block at once (see the module): `soft` is the
    /// pass's `(bias rate (1/s), mass scale, impulse scale)`, `use_bias` adds the position
    /// correction. Needs a [`Self::factor`] for the joints' current rows.
    pub(crate) fn solve_blocks(
        &mut self,
        joints: &mut [FreeJoint],
        bodies: &mut BodySet,
        soft: (f64, f64, f64),
        use_bias: bool,
    ) {
        let (rate, mass_scale, impulse_scale) = soft;
        self.rhs.clear();
        self.rhs
            .extend(joints.iter().map(|j| j.block_rhs(bodies, rate, use_bias)));
        self.solve_rhs();
        for (j, mu) in joints.iter_mut().zip(&self.rhs) {
            j.apply_block(bodies, &(-mu * mass_scale), impulse_scale);
        }
    }

    /// Projects the poses back onto the joints (post-stabilisation, Cline and Pai 2003):
    /// the displacement `M⁻¹ Jᵀ Δλ` with `(J M⁻¹ Jᵀ) Δλ = −C` that removes every row's
    /// position error `C` to first order, through the substep's factorisation. Called after
    /// the substep's positions are integrated, it takes out the drift of integrating turning
    /// bodies along straight lines before it can grow over the substeps.
    pub(crate) fn project_positions(&mut self, joints: &[FreeJoint], bodies: &mut BodySet) {
        self.rhs.clear();
        self.rhs
            .extend(joints.iter().map(|j| j.block_errors(bodies)));
        self.solve_rhs();
        for (j, mu) in joints.iter().zip(&self.rhs) {
            j.displace(bodies, &(-mu));
        }
    }

    /// Solves `(J M⁻¹ Jᵀ) μ = b` for every joint at once: `rhs[k]` is joint `k`'s `b` (its
    /// rows first) and is overwritten with its `μ` (zero for a joint without a node).
    fn solve_rhs(&mut self) {
        let n = self.nodes.len();
        self.work.clear();
        self.work.resize(n, V6::zeros());
        // The system's right-hand side: zero on the bodies, −b on the joints.
        for (k, &node) in self.joint_node.iter().enumerate() {
            if node != NONE {
                self.work[node] = -self.rhs[k];
            }
        }
        // Forward: fold each node into its parent.
        for c in 0..n {
            if let Some(p) = self.nodes[c].parent {
                let y = self.pivot_inv[c] * self.work[c];
                let up = self.nodes[c].coupling.transpose() * y;
                self.work[p] -= up;
            }
        }
        // Backward: parents first.
        for c in (0..n).rev() {
            let mut y = self.work[c];
            if let Some(p) = self.nodes[c].parent {
                y -= self.nodes[c].coupling * self.work[p];
            }
            self.work[c] = self.pivot_inv[c] * y;
        }
        for (k, &node) in self.joint_node.iter().enumerate() {
            self.rhs[k] = if node != NONE {
                self.work[node]
            } else {
                V6::zeros()
            };
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::geometry::{Shape, V3};
    use crate::model::{Ball, Revolute};
    use crate::pipeline::{BodyBuilder, Effect, Effects, JointBuilder, World};

    /// Links of 0.1 m alternating 1 kg and `heavy` kg on ball joints from a fixed anchor,
    /// and, with `closed`, a hinge from the second link to the fifth (a loop).
    fn chain(heavy: f64, closed: bool) -> World {
        let mut w = World::builder(Effects::of(&[Effect::Joints, Effect::Gravity]))
            .dt(1e-3)
            .gravity(V3::new(0.0, 0.0, -9.81))
            .build();
        let ground = w.insert_body(BodyBuilder::fixed(Shape::Sphere { radius: 0.01 }));
        let mut prev = ground;
        let mut links = Vec::new();
        for k in 0..6 {
            let mass = if k % 2 == 0 { 1.0 } else { heavy };
            let b = w.insert_body(
                BodyBuilder::dynamic(Shape::Sphere { radius: 0.03 })
                    .mass(mass)
                    .position(V3::new(0.1 * (k as f64 + 1.0), 0.0, 0.0)),
            );
            let anchor = V3::new(0.1 * k as f64, 0.0, 0.0);
            w.insert_joint(JointBuilder::new(&Ball, prev, b).anchor(anchor))
                .unwrap();
            prev = b;
            links.push(b);
        }
        if closed {
            let hinge = JointBuilder::new(&Revolute::new(V3::y()), links[1], links[4]);
            w.insert_joint(hinge.anchor(V3::new(0.2, 0.0, 0.0)))
                .unwrap();
        }
        w
    }

    /// The largest rate of any joint row after the step (m/s or rad/s): the relax pass is the
    /// step's last change to the velocities, so a forest solved exactly ends at rest.
    fn largest_row_rate(w: &World) -> f64 {
        w.joints
            .iter()
            .map(|j| j.block_rhs(&w.bodies, 0.0, false).amax())
            .fold(0.0, f64::max)
    }

    #[test]
    fn a_forest_of_joints_ends_each_step_with_every_row_at_rest() {
        let mut w = chain(1000.0, false);
        for _ in 0..200 {
            w.step().unwrap();
            assert!(w.joint_graph.usable());
            // Rounding of speeds about 1 m/s through a 1:1000 system.
            let rate = largest_row_rate(&w);
            assert!(rate < 1e-9, "a row moves at {rate} at t = {}", w.time());
        }
    }

    #[test]
    fn joints_that_close_a_loop_are_solved_one_after_another() {
        let mut w = chain(1.0, true);
        let mut moving = 0.0f64;
        for _ in 0..200 {
            w.step().unwrap();
            assert!(!w.joint_graph.usable(), "a loop is not a forest");
            moving = moving.max(largest_row_rate(&w));
        }
        // One Gauss–Seidel pass per substep leaves the loop's rows short of rest.
        assert!(moving > 1e-6, "{moving}");
        for b in w.bodies() {
            assert!(b.position().iter().all(|x| x.is_finite()));
        }
    }

    #[test]
    fn two_joints_to_the_still_world_close_a_loop_through_it() {
        let mut w = chain(1.0, false);
        let ground = w.body_handles().next().unwrap();
        let last = w.body_handles().last().unwrap();
        w.insert_joint(JointBuilder::new(&Ball, last, ground).anchor(V3::new(0.6, 0.0, 0.0)))
            .unwrap();
        w.step().unwrap();
        assert!(!w.joint_graph.usable());
    }
}
