//! Space Foosball rendering with wgpu (paper §5): the table in space, characters from
//! their boxes in team colours, the ball scaled up as it rises with a shadow blob,
//! particles on kicks, bounces and goals, the score, and the cabinet's screens.
//!
//! "The paper" and its section numbers (§5) refer to Bang, Heo, Kim and Kim, "Space
//! Foosball: Coupling Tangible Interfaces with a Real-time Game Physics Engine"; what the
//! project takes from it, section by section, is in docs/paper.md in the repository.
//!
//! The renderer draws a view model ([`view`]): a [`FrameSnapshot`] of plain values
//! (table geometry, teams, character looks, poses) that the program fills in from the
//! game; this crate depends on neither the game nor the physics; the match thread publishes snapshots and the render thread interpolates
//! between the two newest ([`FrameSnapshot::at_time`]), so a slow frame never blocks
//! physics. [`Renderer`] renders offscreen on whatever adapter exists, including Mesa's
//! software Vulkan driver (lavapipe); [`render_to_rgba`] is the one-shot form.

pub mod camera;
mod characters;
pub mod demo;
pub mod font;
mod gpu;
mod image;
mod instances;
mod overlay;
pub mod scene;
pub mod view;
mod window;

#[cfg(test)]
mod fixture;

pub use camera::Camera;
pub use gpu::{AdapterSummary, Renderer, MAX_SIDE};
pub use image::RgbaImage;
pub use scene::{ball_visual_scale, Hud, Screen};
pub use view::{
    BallSnapshot, CharacterKind, CharacterLook, EventKind, FrameSnapshot, ManSnapshot, RenderEvent,
    RodGeometry, RodPose, TableGeometry, Team,
};
pub use window::{DrawTimes, PresentChoice, WindowRenderer};

/// Why a picture could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No graphics adapter at all, not even a software one.
    #[error(
        "no graphics adapter found ({0}); for software rendering install Mesa's Vulkan \
         drivers (Debian/Ubuntu: `apt-get install mesa-vulkan-drivers`)"
    )]
    NoAdapter(String),
    /// The adapter refused to open a device.
    #[error("could not open the graphics device: {0}")]
    Device(String),
    /// The requested image size is zero or too large.
    #[error("image size {width}x{height} is not allowed (each side 1..={max})")]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// Largest side.
        max: u32,
    },
    /// The GPU reported an error while rendering or reading back.
    #[error("GPU error: {0}")]
    Gpu(String),
    /// The window's surface could not be created or configured.
    #[error("could not draw to the window: {0}")]
    Surface(String),
    /// Writing a PNG failed.
    #[error("could not write PNG {path}: {message}")]
    Png {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
}

/// Renders one picture of `screen` showing `snapshot` offscreen, `width × height`
/// pixels, on the first adapter available. Opens a device each call: for many frames
/// keep a [`Renderer`].
pub fn render_to_rgba(
    snapshot: &FrameSnapshot,
    screen: Screen,
    width: u32,
    height: u32,
) -> Result<RgbaImage, RenderError> {
    Renderer::new()?.render_to_rgba(snapshot, screen, width, height)
}
