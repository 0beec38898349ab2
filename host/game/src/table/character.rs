//! Character types: the men on the rods as physical parameters (paper §5).
//!
//! A character is a set of boxes hinged at the shoulder on its rod (paper §5.1). All
//! lengths are metres, in the **man frame**: origin on the rod axis at the man's
//! centre, `y` along the rod (the table's `y`), `z` "up the man" (from the foot towards
//! the head; at rod angle 0 it is the table's `+z`, feet down), `x` completing a
//! right-handed frame (the table's `x` at angle 0).
//!
//! The two types trade reach against width, and that changes play, not only the look:
//!
//! | | [`CharacterType::TallThin`] | [`CharacterType::ShortWide`] |
//! |---|---|---|
//! | foot reach (lever arm) | long: the foot moves faster for the same spin (`v = reach · ω`) and reaches balls further from the rod | short: slower foot, smaller reach |
//! | blocking width (body, foot along the rod) | narrow: shots pass more easily | wide: covers more of the goal |
//! | mass | light | heavy: loses less speed in a collision when the physics lets men swing at the shoulder |
//!
//! so tall-and-thin is good in attack and poor in defence, short-and-wide the opposite.

use serde::{Deserialize, Serialize};

/// The kinds of character a team can choose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CharacterType {
    /// Longer reach and lever, faster foot, narrow body: good in attack.
    TallThin,
    /// Wider blocking body, shorter lever: good in defence.
    ShortWide,
}

impl CharacterType {
    /// The physical parameters of this type.
    pub fn params(self) -> CharacterParams {
        match self {
            CharacterType::TallThin => CharacterParams {
                body_width_m: 0.020,
                body_depth_m: 0.012,
                head_height_m: 0.030,
                shoulder_height_m: 0.010,
                foot_reach_m: 0.096,
                foot_width_m: 0.018,
                mass_kg: 0.080,
            },
            CharacterType::ShortWide => CharacterParams {
                body_width_m: 0.034,
                body_depth_m: 0.020,
                head_height_m: 0.020,
                shoulder_height_m: 0.005,
                foot_reach_m: 0.088,
                foot_width_m: 0.030,
                mass_kg: 0.120,
            },
        }
    }
}

/// Physical parameters of one character (man). Metres and kilograms, man frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CharacterParams {
    /// Width of the body along the rod (`y`), m: the blocking width.
    pub body_width_m: f64,
    /// Thickness of the body across the rod (`x`), m.
    pub body_depth_m: f64,
    /// Top of the head above the rod axis (`+z`), m.
    pub head_height_m: f64,
    /// Shoulder hinge above the rod axis (`+z`), m: where the character is hinged to
    /// the rod (paper §5.1).
    pub shoulder_height_m: f64,
    /// Distance from the rod axis to the sole of the foot (`−z`), m: the lever arm of a
    /// kick; the foot's speed is `foot_reach_m · ω`.
    pub foot_reach_m: f64,
    /// Width of the foot along the rod (`y`), m.
    pub foot_width_m: f64,
    /// Mass of the whole character, kg.
    pub mass_kg: f64,
}

/// An axis-aligned box in the man frame: centre and half extents, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ManBox {
    /// Centre `[x, y, z]`, m.
    pub centre: [f64; 3],
    /// Half extents `[x, y, z]`, m.
    pub half_extents: [f64; 3],
}

impl CharacterParams {
    /// The boxes that make up the character, man frame: the body (head down to the hip)
    /// and the leg with the foot (hip down to the sole). The hip is at 40 % of the
    /// reach below the axis.
    pub fn boxes(&self) -> [ManBox; 2] {
        let hip = -0.4 * self.foot_reach_m;
        let body = ManBox {
            centre: [0.0, 0.0, 0.5 * (self.head_height_m + hip)],
            half_extents: [
                0.5 * self.body_depth_m,
                0.5 * self.body_width_m,
                0.5 * (self.head_height_m - hip),
            ],
        };
        let leg = ManBox {
            centre: [0.0, 0.0, 0.5 * (hip - self.foot_reach_m)],
            half_extents: [
                0.5 * self.body_depth_m,
                0.5 * self.foot_width_m,
                0.5 * (hip + self.foot_reach_m),
            ],
        };
        [body, leg]
    }

    /// Half of the widest extent along the rod (body or foot), m: how far from its
    /// centre a man touches things along `y`.
    pub fn half_width_m(&self) -> f64 {
        0.5 * self.body_width_m.max(self.foot_width_m)
    }

    /// Checks every value is finite and positive and the shape is consistent; the
    /// message names the field.
    pub fn validate(&self) -> Result<(), String> {
        let fields = [
            ("body_width_m", self.body_width_m),
            ("body_depth_m", self.body_depth_m),
            ("head_height_m", self.head_height_m),
            ("foot_reach_m", self.foot_reach_m),
            ("foot_width_m", self.foot_width_m),
            ("mass_kg", self.mass_kg),
        ];
        for (name, v) in fields {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{name} must be a positive number, got {v}"));
            }
        }
        if !(self.shoulder_height_m.is_finite()
            && self.shoulder_height_m >= 0.0
            && self.shoulder_height_m < self.head_height_m)
        {
            return Err(format!(
                "shoulder_height_m must be within 0…head_height_m ({}), got {}",
                self.head_height_m, self.shoulder_height_m
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tall_thin_reaches_further_short_wide_blocks_wider() {
        let tall = CharacterType::TallThin.params();
        let wide = CharacterType::ShortWide.params();
        assert!(tall.foot_reach_m > wide.foot_reach_m);
        assert!(wide.half_width_m() > tall.half_width_m());
        assert!(wide.mass_kg > tall.mass_kg);
        tall.validate().unwrap();
        wide.validate().unwrap();
    }

    #[test]
    fn boxes_span_head_to_foot() {
        let p = CharacterType::TallThin.params();
        let [body, leg] = p.boxes();
        let top = body.centre[2] + body.half_extents[2];
        let bottom = leg.centre[2] - leg.half_extents[2];
        assert!((top - p.head_height_m).abs() < 1e-12);
        assert!((bottom + p.foot_reach_m).abs() < 1e-12);
        // Body and leg meet at the hip.
        let body_bottom = body.centre[2] - body.half_extents[2];
        let leg_top = leg.centre[2] + leg.half_extents[2];
        assert!((body_bottom - leg_top).abs() < 1e-12);
    }

    #[test]
    fn validation_names_the_field() {
        let mut p = CharacterType::ShortWide.params();
        p.foot_reach_m = -0.01;
        assert!(p.validate().unwrap_err().contains("foot_reach_m"));
        let mut p = CharacterType::ShortWide.params();
        p.mass_kg = f64::NAN;
        assert!(p.validate().unwrap_err().contains("mass_kg"));
    }
}
