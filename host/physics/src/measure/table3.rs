//! The paper's Table 3, measured on this crate: operation counts from one run on the
//! [`Counted`] scalar, times (ns per op) from a repeated loop on `f64` — the same generic code.

use super::matrix_form as mf;
use super::{count_ops, Counted, OpCounts};
use crate::algebra::{dse3, se3, AInertia, Inertia, Sym3, Vec3, SE3};
use crate::Real;
use serde::Serialize;
use std::hint::black_box;
use std::time::Instant;

/// Counts (and optionally time) of one form of one operation.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Measured {
    /// Multiplications.
    pub mul: u64,
    /// Additions and subtractions.
    pub add: u64,
    /// Divisions (not in the paper's table; reported for completeness).
    pub div: u64,
    /// Nanoseconds per operation (f64), when timed.
    pub ns: Option<f64>,
}

/// The paper's figures for one form.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
pub struct PaperCounts {
    /// Multiplications.
    pub mul: u64,
    /// Additions.
    pub add: u64,
}

/// The paper's figures for both forms.
#[derive(Clone, Copy, Debug, Serialize, PartialEq, Eq)]
pub struct Paper {
    /// Geometric computation.
    pub geometric: PaperCounts,
    /// Matrix-based computation.
    pub matrix: PaperCounts,
}

/// One row of Table 3.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    /// Operation name as in the paper.
    pub op: &'static str,
    /// This crate's geometric form.
    pub geometric: Measured,
    /// This crate's 6×6 matrix form (nalgebra `Matrix6`).
    pub matrix: Measured,
    /// The paper's counts.
    pub paper: Paper,
}

/// The whole table.
#[derive(Clone, Debug, Serialize)]
pub struct Table3 {
    /// Rows in the paper's order, then the Eq. (6) step.
    pub rows: Vec<Row>,
}

const fn paper(gm: u64, ga: u64, mm: u64, ma: u64) -> Paper {
    Paper {
        geometric: PaperCounts { mul: gm, add: ga },
        matrix: PaperCounts { mul: mm, add: ma },
    }
}

/// Operation names and the paper's counts (Table 3, and §4.4 for Eq. 6).
pub const PAPER: [(&str, Paper); 6] = [
    ("Ad(SE3, se3)", paper(24, 18, 63, 48)),
    ("ad(se3, se3)", paper(18, 12, 36, 30)),
    ("Inertia * se3", paper(24, 18, 36, 30)),
    ("Inertia.Xform(SE3)", paper(101, 66, 459, 378)),
    ("AInertia.Xform(SE3)", paper(294, 210, 459, 378)),
    ("Eq. (6) step", paper(360, 269, 643, 485)),
];

/// Fixed, generic inputs (every entry non-trivial) for all operations.
pub struct Inputs<T: Real> {
    /// A transform.
    pub t: SE3<T>,
    /// Two twists.
    pub v: se3<T>,
    /// A second twist.
    pub w: se3<T>,
    /// A body inertia.
    pub j: Inertia<T>,
    /// An articulated inertia (full 21 entries).
    pub ja: AInertia<T>,
}

impl<T: Real> Inputs<T> {
    /// The standard inputs.
    pub fn new() -> Self {
        let c = |x: f64| T::from_f64(x);
        let v3 = |a: f64, b: f64, d: f64| Vec3::new(c(a), c(b), c(d));
        let t = SE3::exp(&se3::new(v3(0.3, -0.7, 0.4), v3(0.5, 0.2, -0.9)));
        let v = se3::new(v3(0.11, -0.52, 0.33), v3(1.4, -0.25, 0.6));
        let w = se3::new(v3(-0.21, 0.42, 0.93), v3(-0.4, 0.75, 0.16));
        let j = Inertia::from_com(
            c(1.7),
            v3(0.05, -0.02, 0.13),
            Sym3::new(c(0.03), c(0.025), c(0.021), c(0.002), c(-0.001), c(0.0015)),
        );
        let f = dse3::new(v3(0.3, 0.1, -0.2), v3(0.25, -0.6, 0.4));
        let ja = j.to_ainertia() + f.kron_self(c(0.5));
        Self { t, v, w, j, ja }
    }
}

impl<T: Real> Default for Inputs<T> {
    fn default() -> Self {
        Self::new()
    }
}

/// Eq. (6) in the geometric form, as Table 2:
/// `J[i-1] = I[i-1] + (J[i] - (eta*eta)/(S[i]*eta)).Xform(Inv(f[i]))` with `eta = J[i]*S[i]`;
/// the rank-one term is formed as `(eta/Ω) ⊗ eta` and `Xform(Inv(f))` without forming the
/// inverse.
#[inline]
pub fn eq6_step<T: Real>(
    j_parent: &Inertia<T>,
    j_hat: &AInertia<T>,
    s: &se3<T>,
    f: &SE3<T>,
) -> AInertia<T> {
    let eta = j_hat.mul_twist(s);
    let omega = s.dot(&eta);
    let theta = eta.kron_self(T::one() / omega);
    *j_parent + (*j_hat - theta).xform_inv(f)
}

type Op<T> = fn(&Inputs<T>);

/// Op `k` of the table in the geometric form; the whole result goes through `black_box` so
/// no part of the work can be optimised away when timed.
fn geometric<T: Real>(k: usize) -> Op<T> {
    match k {
        0 => |x| {
            black_box(x.t.ad(&x.v));
        },
        1 => |x| {
            black_box(x.v.ad(&x.w));
        },
        2 => |x| {
            black_box(x.j.mul_twist(&x.v));
        },
        3 => |x| {
            black_box(x.j.xform(&x.t));
        },
        4 => |x| {
            black_box(x.ja.xform(&x.t));
        },
        _ => |x| {
            black_box(eq6_step(&x.j, &x.ja, &x.v, &x.t));
        },
    }
}

/// Matrix-form inputs, prepared outside the measured region like the geometric ones.
struct MatrixInputs<T: Real> {
    base: Inputs<T>,
    v6: nalgebra::Vector6<T>,
    w6: nalgebra::Vector6<T>,
    j6: nalgebra::Matrix6<T>,
    ja6: nalgebra::Matrix6<T>,
}

impl<T: Real> MatrixInputs<T> {
    fn new() -> Self {
        let base = Inputs::new();
        Self {
            v6: mf::vec6_of_twist(&base.v),
            w6: mf::vec6_of_twist(&base.w),
            j6: mf::inertia_matrix(&base.j),
            ja6: base.ja.to_matrix6(),
            base,
        }
    }
}

type MOp<T> = fn(&MatrixInputs<T>);

fn matrix<T: Real>(k: usize) -> MOp<T> {
    match k {
        0 => |x| {
            black_box(mf::ad(&x.base.t, &x.v6));
        },
        1 => |x| {
            black_box(mf::lie_ad(&x.base.v, &x.w6));
        },
        2 => |x| {
            black_box(mf::inertia_mul(&x.j6, &x.v6));
        },
        3 => |x| {
            black_box(mf::xform(&x.j6, &x.base.t));
        },
        4 => |x| {
            black_box(mf::xform(&x.ja6, &x.base.t));
        },
        _ => |x| {
            black_box(mf::eq7_step(&x.j6, &x.ja6, &x.v6, &x.base.t));
        },
    }
}

fn measured(c: OpCounts, ns: Option<f64>) -> Measured {
    Measured {
        mul: c.mul,
        add: c.add,
        div: c.div,
        ns,
    }
}

/// Nanoseconds per call of `f`: batches of calls sized to ~10 ms, best of 7.
pub fn time_ns<R>(mut f: impl FnMut() -> R) -> f64 {
    let mut iters: u64 = 16;
    loop {
        let t = Instant::now();
        for _ in 0..iters {
            black_box(f());
        }
        if t.elapsed().as_secs_f64() > 0.01 {
            break;
        }
        iters *= 2;
    }
    let mut best = f64::INFINITY;
    for _ in 0..7 {
        let t = Instant::now();
        for _ in 0..iters {
            black_box(f());
        }
        best = best.min(t.elapsed().as_secs_f64() * 1e9 / iters as f64);
    }
    best
}

/// Measures the table: counts always; times when `timed` (f64, in-process loop with
/// `black_box`).
pub fn measure(timed: bool) -> Table3 {
    let gin: Inputs<Counted> = Inputs::new();
    let min: MatrixInputs<Counted> = MatrixInputs::new();
    let gin64: Inputs<f64> = Inputs::new();
    let min64: MatrixInputs<f64> = MatrixInputs::new();
    let rows = PAPER
        .iter()
        .enumerate()
        .map(|(k, &(op, paper))| {
            let (_, gc) = count_ops(|| geometric::<Counted>(k)(&gin));
            let (_, mc) = count_ops(|| matrix::<Counted>(k)(&min));
            let (gt, mt) = if timed {
                let g = geometric::<f64>(k);
                let m = matrix::<f64>(k);
                (
                    Some(time_ns(|| g(black_box(&gin64)))),
                    Some(time_ns(|| m(black_box(&min64)))),
                )
            } else {
                (None, None)
            };
            Row {
                op,
                geometric: measured(gc, gt),
                matrix: measured(mc, mt),
                paper,
            }
        })
        .collect();
    Table3 { rows }
}

/// Op `k` (row order of [`PAPER`]) in both forms on the `f64` inputs, as 6×6 matrices (twist
/// and wrench results in the first column) for cross-checking.
pub fn both_forms(k: usize) -> (nalgebra::Matrix6<f64>, nalgebra::Matrix6<f64>) {
    let g: Inputs<f64> = Inputs::new();
    let m: MatrixInputs<f64> = MatrixInputs::new();
    let col = |v: [f64; 6]| {
        let mut x = nalgebra::Matrix6::zeros();
        x.fixed_view_mut::<6, 1>(0, 0)
            .copy_from(&nalgebra::Vector6::from_column_slice(&v));
        x
    };
    let colv = |v: nalgebra::Vector6<f64>| {
        let mut x = nalgebra::Matrix6::zeros();
        x.fixed_view_mut::<6, 1>(0, 0).copy_from(&v);
        x
    };
    match k {
        0 => (col(g.t.ad(&g.v).to_array()), colv(mf::ad(&g.t, &m.v6))),
        1 => (col(g.v.ad(&g.w).to_array()), colv(mf::lie_ad(&g.v, &m.w6))),
        2 => (
            col(g.j.mul_twist(&g.v).to_array()),
            colv(mf::inertia_mul(&m.j6, &m.v6)),
        ),
        3 => (
            g.j.xform(&g.t).to_ainertia().to_matrix6(),
            mf::xform(&m.j6, &g.t),
        ),
        4 => (g.ja.xform(&g.t).to_matrix6(), mf::xform(&m.ja6, &g.t)),
        _ => (
            eq6_step(&g.j, &g.ja, &g.v, &g.t).to_matrix6(),
            mf::eq7_step(&m.j6, &m.ja6, &m.v6, &g.t),
        ),
    }
}
