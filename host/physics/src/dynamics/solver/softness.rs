//! Soft constraint coefficients (Box2D v3 `b2Softness`): a constraint behaves like a
//! spring of frequency `hertz` (Hz) and damping ratio `zeta`, integrated implicitly over a
//! substep of `h` seconds.

use crate::transcendental::{ln, powf};

/// The three coefficients of a soft constraint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Softness {
    /// Position error to velocity bias (1/s).
    pub(crate) bias_rate: f64,
    /// Scale of the effective mass (–).
    pub(crate) mass_scale: f64,
    /// Scale of the accumulated impulse subtracted each iteration (–).
    pub(crate) impulse_scale: f64,
}

impl Softness {
    /// From frequency (Hz), damping ratio and substep (s). `hertz = 0` gives a rigid
    /// constraint without position bias.
    pub(crate) fn new(hertz: f64, zeta: f64, h: f64) -> Self {
        if hertz <= 0.0 {
            return Self {
                bias_rate: 0.0,
                mass_scale: 1.0,
                impulse_scale: 0.0,
            };
        }
        let omega = 2.0 * std::f64::consts::PI * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Self {
            bias_rate: omega / a1,
            mass_scale: a2 * a3,
            impulse_scale: a3,
        }
    }

    /// A rigid constraint with position bias `bias_rate` (1/s): no softening of the mass and
    /// no leak of the accumulated impulse, so a resting contact's overlap converges to zero.
    pub(crate) fn rigid(bias_rate: f64) -> Self {
        Self {
            bias_rate,
            mass_scale: 1.0,
            impulse_scale: 0.0,
        }
    }
}

/// How stiff each contact is made (the step's settings, in SI units).
///
/// A soft contact of stiffness `ω = 2π hertz` on a normal row of effective mass `m` settles,
/// under a steady force `F`, at the overlap `F / (m ω²)` (the equilibrium of
/// [`Softness::new`]'s spring): the bottom contacts of a tall tower sink, tilt and let it
/// buckle unless they are stiff. Stiffer contacts hold a tower of equal boxes, but between
/// bodies of very different masses a stiff contact lets the one Gauss–Seidel pass per substep
/// work the light body sideways (measured: a 1 g box under 1 kg creeps 10–50 cm in 20 s
/// at 180 Hz, 5 cm at 120 Hz). So a contact between two moving bodies takes `even_hertz` when
/// their masses are equal and `hertz` from a mass ratio of [`UNEVEN_MASS_RATIO`] on,
/// geometrically in between; against a body that does not move, `static_hertz`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ContactStiffness {
    /// Stiffness of a contact between moving bodies of very different masses (Hz).
    pub(crate) hertz: f64,
    /// Stiffness of a contact between moving bodies of equal mass (Hz).
    pub(crate) even_hertz: f64,
    /// Stiffness against a body that does not move (Hz).
    pub(crate) static_hertz: f64,
    /// Damping ratio (–).
    pub(crate) damping_ratio: f64,
    /// Substep (s).
    pub(crate) substep: f64,
}

/// Mass ratio (heavier / lighter, –) from which a contact between moving bodies takes the
/// stiffness of uneven masses, [`ContactStiffness::hertz`].
pub(crate) const UNEVEN_MASS_RATIO: f64 = 10.0;

impl ContactStiffness {
    /// Stiffness (Hz) of a contact against a body that does not move, or between moving bodies
    /// whose masses are `mass_ratio` (heavier / lighter, ≥ 1) apart.
    pub(crate) fn hertz_for(&self, against_static: bool, mass_ratio: f64) -> f64 {
        if against_static {
            return self.static_hertz;
        }
        if mass_ratio.is_nan() || mass_ratio >= UNEVEN_MASS_RATIO {
            return self.hertz; // also a NaN ratio
        }
        // Geometric interpolation in log(ratio): even_hertz at 1, hertz at UNEVEN_MASS_RATIO.
        let t = (ln(mass_ratio.max(1.0)) / ln(UNEVEN_MASS_RATIO)).clamp(0.0, 1.0);
        self.even_hertz * powf(self.hertz / self.even_hertz, t)
    }

    /// The soft coefficients of such a contact.
    pub(crate) fn softness(&self, against_static: bool, mass_ratio: f64) -> Softness {
        Softness::new(
            self.hertz_for(against_static, mass_ratio),
            self.damping_ratio,
            self.substep,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stiffness_falls_from_even_to_uneven_masses() {
        let k = ContactStiffness {
            hertz: 120.0,
            even_hertz: 180.0,
            static_hertz: 240.0,
            damping_ratio: 10.0,
            substep: 1.0 / 720.0,
        };
        assert_eq!(k.hertz_for(true, 1.0), 240.0);
        assert!((k.hertz_for(false, 1.0) - 180.0).abs() < 1e-9);
        assert_eq!(k.hertz_for(false, 10.0), 120.0);
        assert_eq!(k.hertz_for(false, 1000.0), 120.0);
        assert_eq!(k.hertz_for(false, f64::NAN), 120.0);
        let mid = k.hertz_for(false, 10f64.sqrt());
        assert!((mid - (180.0f64 * 120.0).sqrt()).abs() < 1e-9, "{mid}");
        let (a, b) = (k.hertz_for(false, 2.0), k.hertz_for(false, 5.0));
        assert!(180.0 > a && a > b && b > 120.0);
        // Equal stiffnesses: no change with the ratio.
        let flat = ContactStiffness {
            even_hertz: 120.0,
            ..k
        };
        assert!((flat.hertz_for(false, 3.0) - 120.0).abs() < 1e-9);
    }
}
