//! Shared helpers of the integration tests.
#![allow(dead_code)]

use nalgebra::Matrix6;
use proptest::prelude::*;
use virtual_physics::algebra::{dse3, exp_so3, se3, Inertia, Sym3, Vec3, SE3};

pub fn vec3(r: f64) -> impl Strategy<Value = Vec3<f64>> {
    (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

pub fn twist() -> impl Strategy<Value = se3<f64>> {
    (vec3(2.0), vec3(2.0)).prop_map(|(w, v)| se3::new(w, v))
}

pub fn wrench() -> impl Strategy<Value = dse3<f64>> {
    (vec3(2.0), vec3(2.0)).prop_map(|(m, f)| dse3::new(m, f))
}

/// Transforms with rotation angles up to 3 rad and translations up to 2 m.
pub fn transform() -> impl Strategy<Value = SE3<f64>> {
    (vec3(1.0), 0.0..3.0f64, vec3(2.0)).prop_map(|(d, angle, p)| {
        let n = d.norm().max(1e-3);
        SE3::new(exp_so3(&(d * (angle / n))), p)
    })
}

/// Physically valid inertias: principal moments obeying the triangle inequality, rotated,
/// off-centre.
pub fn inertia() -> impl Strategy<Value = Inertia<f64>> {
    (
        0.1..10.0f64,
        vec3(1.0),
        (0.1..1.0f64, 0.1..1.0f64, 0.1..1.0f64),
        transform(),
    )
        .prop_map(|(m, c, (a, b, d), t)| {
            // Principal moments from a mass distribution (always satisfy triangle inequality).
            let (x, y, z) = (a * a, b * b, d * d);
            let diag = Sym3::new(m * (y + z), m * (x + z), m * (x + y), 0.0, 0.0, 0.0);
            Inertia::from_com(m, c, diag.congruence(&t.r))
        })
}

/// Cholesky succeeds: symmetric positive definite (and symmetric to 1e-12).
pub fn is_spd(m: &Matrix6<f64>) -> bool {
    if (m - m.transpose()).abs().max() > 1e-12 * m.abs().max() {
        return false;
    }
    m.cholesky().is_some()
}

pub fn ad_matrix(t: &SE3<f64>) -> Matrix6<f64> {
    virtual_physics::measure::matrix_form::ad_matrix(t)
}

pub fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

pub fn close6(a: [f64; 6], b: [f64; 6], tol: f64) -> bool {
    a.iter().zip(b.iter()).all(|(x, y)| close(*x, *y, tol))
}

pub fn close_m6(a: &Matrix6<f64>, b: &Matrix6<f64>, tol: f64) -> bool {
    (a - b).abs().max() <= tol * (1.0 + a.abs().max())
}

/// Relative error `‖a − b‖ / ‖b‖`.
pub fn rel_err(a: &[f64], b: &[f64]) -> f64 {
    let num: f64 = a
        .iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt();
    let den: f64 = b.iter().map(|y| y * y).sum::<f64>().sqrt();
    num / den.max(f64::MIN_POSITIVE)
}
