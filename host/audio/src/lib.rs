//! Space Foosball sound: kicks, bounces, the goal ceremony fanfare and menu sounds,
//! synthesised in code ([`synth`]: no asset files, nothing downloaded), and an
//! [`AudioOutput`] that plays them through [cpal](https://docs.rs/cpal).
//!
//! A machine with no audio device plays silently: [`AudioOutput::open`] never fails,
//! it returns a silent output and logs a notice (through the `log` facade) saying why.
//!
//! ```no_run
//! use foosball_audio::{AudioOutput, Sound};
//! let audio = AudioOutput::open();
//! audio.play(Sound::Kick { speed_m_s: 4.0 });
//! audio.play(Sound::GoalFanfare);
//! ```

mod mixer;
pub mod offline;
mod output;
pub mod synth;

pub use mixer::{Mixer, MAX_VOICES};
pub use offline::{mix_timeline, wav_bytes};
pub use output::{AudioOutput, DISABLE_ENV};
pub use synth::SAMPLE_RATE_HZ;

/// A sound the game asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sound {
    /// A man kicked the ball; `speed_m_s` is the ball's speed after the kick, m/s.
    Kick {
        /// Ball speed after the kick, m/s.
        speed_m_s: f32,
    },
    /// The ball bounced on the cloth or a wall; `speed_m_s` is the impact speed, m/s.
    Bounce {
        /// Impact speed, m/s.
        speed_m_s: f32,
    },
    /// The goal ceremony.
    GoalFanfare,
    /// A menu choice moved (a rod spun).
    MenuTick,
    /// A menu choice was confirmed (a rod pushed).
    MenuConfirm,
}

impl Sound {
    /// The sound's samples: mono, [`SAMPLE_RATE_HZ`], within `[-1, 1]`.
    pub fn samples(self) -> Vec<f32> {
        match self {
            Sound::Kick { speed_m_s } => synth::kick(speed_m_s),
            Sound::Bounce { speed_m_s } => synth::bounce(speed_m_s),
            Sound::GoalFanfare => synth::goal_fanfare(),
            Sound::MenuTick => synth::menu_tick(),
            Sound::MenuConfirm => synth::menu_confirm(),
        }
    }

    /// The sound's duration, s.
    pub fn duration_s(self) -> f32 {
        match self {
            Sound::Kick { .. } => synth::KICK_S,
            Sound::Bounce { .. } => synth::BOUNCE_S,
            Sound::GoalFanfare => synth::GOAL_FANFARE_S,
            Sound::MenuTick => synth::MENU_TICK_S,
            Sound::MenuConfirm => synth::MENU_CONFIRM_S,
        }
    }

    /// Short name (`kick`, `bounce`, `goal-fanfare`, `menu-tick`, `menu-confirm`).
    pub fn name(self) -> &'static str {
        match self {
            Sound::Kick { .. } => "kick",
            Sound::Bounce { .. } => "bounce",
            Sound::GoalFanfare => "goal-fanfare",
            Sound::MenuTick => "menu-tick",
            Sound::MenuConfirm => "menu-confirm",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_match_the_samples() {
        for s in [
            Sound::Kick { speed_m_s: 2.0 },
            Sound::Bounce { speed_m_s: 2.0 },
            Sound::GoalFanfare,
            Sound::MenuTick,
            Sound::MenuConfirm,
        ] {
            assert_eq!(
                s.samples().len(),
                synth::samples_for(s.duration_s()),
                "{}",
                s.name()
            );
        }
    }
}
