//! Soft constraint coefficients (Box2D v3 `b2Softness`): a constraint behaves like a
//! spring of frequency `hertz` (Hz) and damping ratio `zeta`, integrated implicitly over a
//! substep of `h` seconds.

/// The three coefficients of a soft constraint.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Softness {
    /// Position error to velocity bias (1/s).
    pub bias_rate: f64,
    /// Scale of the effective mass (–).
    pub mass_scale: f64,
    /// Scale of the accumulated impulse subtracted each iteration (–).
    pub impulse_scale: f64,
}

impl Softness {
    /// From frequency (Hz), damping ratio and substep (s). `hertz = 0` gives a rigid
    /// constraint without position bias.
    pub fn new(hertz: f64, zeta: f64, h: f64) -> Self {
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
    pub fn rigid(bias_rate: f64) -> Self {
        Self {
            bias_rate,
            mass_scale: 1.0,
            impulse_scale: 0.0,
        }
    }
}
