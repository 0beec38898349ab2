//! Property tests of the Lie-group algebra.

mod common;

use common::*;
use proptest::prelude::*;
use virtual_physics::algebra::{exp_so3, log_so3, se3, Vec3, SE3};

fn se3_close(a: &SE3<f64>, b: &SE3<f64>, tol: f64) -> bool {
    (a.r - b.r).abs().max() <= tol && (a.p - b.p).abs().max() <= tol * (1.0 + a.p.abs().max())
}

fn unit(d: Vec3<f64>) -> Vec3<f64> {
    d / d.norm().max(1e-3)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn log_exp_round_trip_generic(d in vec3(1.0), theta in 0.0..3.1f64, v in vec3(3.0)) {
        let xi = se3::new(unit(d) * theta, v);
        let back = SE3::exp(&xi).log();
        prop_assert!(close6(back.to_array(), xi.to_array(), 1e-11), "{xi:?} -> {back:?}");
    }

    #[test]
    fn log_exp_round_trip_near_zero(d in vec3(1.0), e in -16.0..-1.0f64, v in vec3(3.0)) {
        // θ from 1e-16 to 0.1 rad: covers the series and the switch to the closed forms.
        let xi = se3::new(unit(d) * 10f64.powf(e), v);
        let t = SE3::exp(&xi);
        prop_assert!((t.r * t.r.transpose() - nalgebra::Matrix3::identity()).abs().max() < 1e-15);
        let back = t.log();
        prop_assert!(close6(back.to_array(), xi.to_array(), 1e-14), "{xi:?} -> {back:?}");
    }

    #[test]
    fn log_exp_round_trip_near_pi(d in vec3(1.0), e in -12.0..-2.0f64, v in vec3(3.0)) {
        // θ = π − δ with δ from 1e-12 to 1e-2 rad.
        let theta = std::f64::consts::PI - 10f64.powf(e);
        let xi = se3::new(unit(d) * theta, v);
        let back = SE3::exp(&xi).log();
        prop_assert!(close6(back.to_array(), xi.to_array(), 1e-9), "{xi:?} -> {back:?}");
    }

    #[test]
    fn exp_log_round_trip_at_and_near_pi(d in vec3(1.0), e in -17.0..-6.0f64, v in vec3(3.0)) {
        // Within 1e-6 of π (and at π) the axis sign is ambiguous: compare transforms.
        let theta = std::f64::consts::PI - 10f64.powf(e);
        for th in [theta, std::f64::consts::PI] {
            let t = SE3::exp(&se3::new(unit(d) * th, v));
            let back = SE3::exp(&t.log());
            prop_assert!(se3_close(&back, &t, 1e-12), "{t:?} vs {back:?}");
            // The angle is atan2(…) ≤ π; the norm of `θ · col / |col|`, computed again here,
            // carries a few ulps of rounding (ulp(π) = 4.4e-16).
            prop_assert!(t.log().w.norm() <= std::f64::consts::PI * (1.0 + 8.0 * f64::EPSILON));
        }
    }

    #[test]
    fn exp_log_round_trip_transforms(t in transform()) {
        prop_assert!(se3_close(&SE3::exp(&t.log()), &t, 1e-12));
        prop_assert!((exp_so3(&log_so3(&t.r)) - t.r).abs().max() < 1e-12);
    }

    #[test]
    fn ad_is_a_group_homomorphism(a in transform(), b in transform(), v in twist()) {
        let lhs = (a * b).ad(&v);
        let rhs = a.ad(&b.ad(&v));
        prop_assert!(close6(lhs.to_array(), rhs.to_array(), 1e-12));
        // Ad of the inverse, and the no-inverse form.
        let inv = a.inverse().ad(&v);
        prop_assert!(close6(inv.to_array(), a.ad_inv(&v).to_array(), 1e-12));
        prop_assert!(close6(a.ad_inv(&a.ad(&v)).to_array(), v.to_array(), 1e-12));
        prop_assert!(se3_close(&(a * a.inverse()), &SE3::identity(), 1e-14));
    }

    #[test]
    fn ad_matches_its_matrix(t in transform(), v in twist()) {
        let m = ad_matrix(&t) * nalgebra::Vector6::from_column_slice(&v.to_array());
        prop_assert!(close6(t.ad(&v).to_array(), [m[0], m[1], m[2], m[3], m[4], m[5]], 1e-12));
    }

    #[test]
    fn dad_is_the_dual_of_ad(t in transform(), f in wrench(), v in twist()) {
        prop_assert!(close(t.dad(&f).dot(&v), f.dot(&t.ad(&v)), 1e-12));
        prop_assert!(close(t.dad_inv(&f).dot(&v), f.dot(&t.ad_inv(&v)), 1e-12));
        prop_assert!(close6(t.dad_inv(&t.dad(&f)).to_array(), f.to_array(), 1e-12));
    }

    #[test]
    fn small_dad_is_the_dual_of_small_ad(v in twist(), w in twist(), f in wrench()) {
        prop_assert!(close(v.dad(&f).dot(&w), f.dot(&v.ad(&w)), 1e-12));
    }

    #[test]
    fn jacobi_identity(x in twist(), y in twist(), z in twist()) {
        let j = x.ad(&y.ad(&z)) + y.ad(&z.ad(&x)) + z.ad(&x.ad(&y));
        prop_assert!(j.to_array().iter().all(|c| c.abs() < 1e-12), "{j:?}");
        // Antisymmetry.
        prop_assert!(close6(x.ad(&y).to_array(), (-y.ad(&x)).to_array(), 1e-15));
    }

    #[test]
    fn ad_of_adjoint_is_conjugation(t in transform(), x in twist(), y in twist()) {
        // Ad_T [X, Y] = [Ad_T X, Ad_T Y]
        let lhs = t.ad(&x.ad(&y));
        let rhs = t.ad(&x).ad(&t.ad(&y));
        prop_assert!(close6(lhs.to_array(), rhs.to_array(), 1e-11));
    }

    #[test]
    fn inertia_xform_composes_and_matches_matrix(j in inertia(), a in transform(), b in transform()) {
        let lhs = j.xform(&(a * b)).to_ainertia().to_matrix6();
        let rhs = j.xform(&a).xform(&b).to_ainertia().to_matrix6();
        prop_assert!(close_m6(&lhs, &rhs, 1e-11));
        let x = ad_matrix(&a);
        let m = x.transpose() * j.to_ainertia().to_matrix6() * x;
        prop_assert!(close_m6(&j.xform(&a).to_ainertia().to_matrix6(), &m, 1e-12));
        let inv = j.xform_inv(&a).to_ainertia().to_matrix6();
        prop_assert!(close_m6(&inv, &j.xform(&a.inverse()).to_ainertia().to_matrix6(), 1e-12));
        prop_assert!(close_m6(&j.xform(&a).xform_inv(&a).to_ainertia().to_matrix6(),
                              &j.to_ainertia().to_matrix6(), 1e-12));
    }

    #[test]
    fn ainertia_xform_composes_and_matches_matrix(
        j in inertia(), f in wrench(), a in transform(), b in transform()
    ) {
        let ja = j.to_ainertia() + f.kron_self(0.7);
        let lhs = ja.xform(&(a * b)).to_matrix6();
        let rhs = ja.xform(&a).xform(&b).to_matrix6();
        prop_assert!(close_m6(&lhs, &rhs, 1e-11));
        let x = ad_matrix(&a);
        prop_assert!(close_m6(&ja.xform(&a).to_matrix6(), &(x.transpose() * ja.to_matrix6() * x), 1e-12));
        prop_assert!(close_m6(&ja.xform_inv(&a).to_matrix6(), &ja.xform(&a.inverse()).to_matrix6(), 1e-12));
    }

    #[test]
    fn inertia_stays_symmetric_positive_definite(j in inertia(), t in transform(), s in twist()) {
        prop_assert!(is_spd(&j.to_ainertia().to_matrix6()));
        let x = j.xform(&t);
        prop_assert!(is_spd(&x.to_ainertia().to_matrix6()));
        prop_assert!(is_spd(&j.to_ainertia().xform(&t).to_matrix6()));
        // The Eq. (6) update of a child onto a parent stays SPD.
        let child = j.to_ainertia();
        let eta = child.mul_twist(&s);
        let upd = j + (child - eta.kron_self(1.0 / s.dot(&eta))).xform_inv(&t);
        prop_assert!(is_spd(&upd.to_matrix6()));
        // Momentum: the 10-parameter product equals the 6×6 one.
        let m = j.to_ainertia().to_matrix6() * nalgebra::Vector6::from_column_slice(&s.to_array());
        prop_assert!(close6(j.mul_twist(&s).to_array(), [m[0], m[1], m[2], m[3], m[4], m[5]], 1e-12));
    }

    #[test]
    fn kronecker_and_reciprocal_products(f in wrench(), g in wrench(), v in twist()) {
        // (F ⊗ G) V = ½ (F ⟨G, V⟩ + G ⟨F, V⟩)
        let lhs = (f * g).mul_twist(&v);
        let rhs = (f * g.dot(&v) + g * f.dot(&v)) * 0.5;
        prop_assert!(close6(lhs.to_array(), rhs.to_array(), 1e-12));
        prop_assert!(close_m6(&f.kron(&f).to_matrix6(), &f.kron_self(1.0).to_matrix6(), 1e-14));
        prop_assert!(close(v * f, f * v, 0.0));
    }
}

#[test]
fn exp_of_known_rotation() {
    let t = SE3::exp(&se3::new(
        Vec3::new(0.0, 0.0, std::f64::consts::FRAC_PI_2),
        Vec3::new(1.0, 0.0, 0.0),
    ));
    // Quarter turn about z.
    assert!((t.r * Vec3::new(1.0, 0.0, 0.0) - Vec3::new(0.0, 1.0, 0.0)).norm() < 1e-15);
    // Screw motion: p = (I + B[w] + C[w]²) v with θ = π/2: (2/π, 2/π, 0).
    let k = 2.0 / std::f64::consts::PI;
    assert!((t.p - Vec3::new(k, k, 0.0)).norm() < 1e-15, "{:?}", t.p);
}
