//! Drawing to a window: the same pipelines as offscreen pictures, on a wgpu surface.
//!
//! The renderer knows no windowing library: anything with a raw window and display
//! handle (a `winit` window in an `Arc`) becomes a surface. The surface is configured
//! with an sRGB format when the adapter offers one (the scene's colours assume it; where
//! the surface itself is not sRGB, as a WebGPU canvas, it is drawn through an sRGB view
//! of it) and the chosen present mode. [`WindowRenderer::draw`] can also hand back the very frame
//! it presented (`capture`), read from the swapchain image before presenting, for the
//! test that checks what the running window shows.

use crate::gpu::{
    copy_to_buffer, open_device_async, padded_row_bytes, popped_error, read_buffer, AdapterSummary,
    DEPTH_FORMAT,
};
use crate::image::RgbaImage;
use crate::scene::{self, Hud, Screen};
use crate::view::FrameSnapshot;
use crate::{RenderError, Renderer};
// web-time: std's Instant on native targets, the page's clock in a browser (std's
// panics on wasm32).
use web_time::Instant;

/// How frames reach the screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PresentChoice {
    /// Wait for vertical blank (FIFO): no tearing, at most the display's refresh rate.
    #[default]
    Vsync,
    /// Mailbox where the adapter offers it (newest frame replaces a queued one: low
    /// latency, no tearing), else FIFO.
    LowLatency,
}

/// Where one [`WindowRenderer::draw`] spent its time on the calling thread, ms. On a
/// software adapter the GPU's work runs on the driver's own threads and shows here as
/// waiting: in `acquire` (for a free swapchain image) and `present`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DrawTimes {
    /// Waiting for the surface's next image (the previous frames' GPU work, vsync).
    pub acquire_ms: f64,
    /// Building the scene's instance lists from the snapshot (CPU).
    pub build_ms: f64,
    /// Uploading the instances, recording and submitting the command buffer.
    pub encode_ms: f64,
    /// Presenting (and, when capturing, reading the frame back).
    pub present_ms: f64,
}

/// A [`Renderer`] drawing into a window's surface.
pub struct WindowRenderer {
    renderer: Renderer,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    depth: wgpu::Texture,
    /// The format the frame is drawn through (sRGB: the surface's, or a view of it).
    view_format: wgpu::TextureFormat,
    can_copy: bool,
    last_times: DrawTimes,
}

impl WindowRenderer {
    /// Opens an adapter that can present to `window` (a hardware GPU, else a software
    /// one such as lavapipe) and configures its surface at `width × height` pixels.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn new(
        window: impl Into<wgpu::SurfaceTarget<'static>>,
        width: u32,
        height: u32,
        present: PresentChoice,
    ) -> Result<WindowRenderer, RenderError> {
        let instance = crate::gpu::new_instance();
        pollster::block_on(Self::on_instance(instance, window, width, height, present))
    }

    /// [`WindowRenderer::new`] in a browser, on the page's canvas: WebGPU where the
    /// browser gives an adapter for it, else WebGL2 (whichever the embedding crate's
    /// wgpu features enable). Awaited: WebGPU's promises complete only once the page's
    /// event loop runs.
    #[cfg(target_arch = "wasm32")]
    pub async fn new_in_browser(
        window: impl Into<wgpu::SurfaceTarget<'static>>,
        width: u32,
        height: u32,
        present: PresentChoice,
    ) -> Result<WindowRenderer, RenderError> {
        let instance = crate::gpu::new_browser_instance().await;
        Self::on_instance(instance, window, width, height, present).await
    }

    async fn on_instance(
        instance: wgpu::Instance,
        window: impl Into<wgpu::SurfaceTarget<'static>>,
        width: u32,
        height: u32,
        present: PresentChoice,
    ) -> Result<WindowRenderer, RenderError> {
        let surface = instance
            .create_surface(window)
            .map_err(|e| RenderError::Surface(e.to_string()))?;
        let (adapter, device, queue) = open_device_async(&instance, Some(&surface)).await?;
        let caps = surface.get_capabilities(&adapter);
        let format = choose_format(&caps.formats).ok_or_else(|| {
            RenderError::Surface("the adapter cannot present to this window".into())
        })?;
        // A surface with no sRGB format (a WebGPU canvas offers only linear ones) is
        // drawn through an sRGB view of its texture.
        let view_format = format.add_srgb_suffix();
        let view_formats = if view_format == format {
            vec![]
        } else {
            vec![view_format]
        };
        let present_mode = match present {
            PresentChoice::LowLatency
                if caps.present_modes.contains(&wgpu::PresentMode::Mailbox) =>
            {
                wgpu::PresentMode::Mailbox
            }
            _ => wgpu::PresentMode::Fifo,
        };
        let can_copy = caps.usages.contains(wgpu::TextureUsages::COPY_SRC);
        let mut usage = wgpu::TextureUsages::RENDER_ATTACHMENT;
        if can_copy {
            usage |= wgpu::TextureUsages::COPY_SRC;
        }
        let config = wgpu::SurfaceConfiguration {
            usage,
            format,
            width: width.max(1),
            height: height.max(1),
            present_mode,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps
                .alpha_modes
                .first()
                .copied()
                .unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats,
        };
        let renderer = Renderer::with_device(&adapter, device, queue, view_format)?;
        surface.configure(&renderer.device, &config);
        let depth = depth_texture(&renderer.device, config.width, config.height);
        Ok(WindowRenderer {
            renderer,
            surface,
            config,
            depth,
            view_format,
            can_copy,
            last_times: DrawTimes::default(),
        })
    }

    /// The adapter in use.
    pub fn adapter(&self) -> &AdapterSummary {
        self.renderer.adapter()
    }

    /// The present mode in use, in words (`Fifo`, `Mailbox`).
    pub fn present_mode(&self) -> String {
        format!("{:?}", self.config.present_mode)
    }

    /// Where the last [`WindowRenderer::draw`] spent its time.
    pub fn last_draw_times(&self) -> DrawTimes {
        self.last_times
    }

    /// The surface size, pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// Follows a window resize; a zero side (minimised) keeps the old size.
    pub fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 || (width, height) == self.size() {
            return;
        }
        self.config.width = width.min(crate::MAX_SIDE);
        self.config.height = height.min(crate::MAX_SIDE);
        self.surface.configure(&self.renderer.device, &self.config);
        self.depth = depth_texture(&self.renderer.device, self.config.width, self.config.height);
    }

    /// Draws `snap` on `screen` with `hud` and presents it. With `capture`, returns
    /// the presented picture (RGBA): read from the swapchain image when the surface
    /// allows copies, else the same frame rendered offscreen at the window's size.
    /// `Ok(None)` when not capturing or when the surface had no image this time (it
    /// was outdated by a resize and has been reconfigured; the next frame draws).
    pub fn draw(
        &mut self,
        snap: &FrameSnapshot,
        screen: Screen,
        hud: &Hud,
        capture: bool,
    ) -> Result<Option<RgbaImage>, RenderError> {
        let (width, height) = self.size();
        let ms = |since: Instant| since.elapsed().as_secs_f64() * 1e3;
        let t0 = Instant::now();
        let frame = match self.surface.get_current_texture() {
            Ok(f) => f,
            Err(wgpu::SurfaceError::Outdated | wgpu::SurfaceError::Lost) => {
                self.surface.configure(&self.renderer.device, &self.config);
                return Ok(None);
            }
            Err(wgpu::SurfaceError::Timeout) => return Ok(None),
            Err(e) => return Err(RenderError::Surface(e.to_string())),
        };
        let acquire_ms = ms(t0);
        let t1 = Instant::now();
        let scene = scene::build_with_hud(snap, screen, hud, width, height);
        let build_ms = ms(t1);
        let t2 = Instant::now();
        // A handle (wgpu devices are reference counted): encoding borrows the renderer.
        let device = &self.renderer.device.clone();
        device.push_error_scope(wgpu::ErrorFilter::Validation);
        let view = frame.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.view_format),
            ..Default::default()
        });
        let depth_view = self.depth.create_view(&Default::default());
        let mut enc = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("window frame"),
        });
        self.renderer
            .encode_scene(&mut enc, &scene, &view, &depth_view, width, height);
        let padded_row = padded_row_bytes(width);
        let readback = (capture && self.can_copy).then(|| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("window capture"),
                size: u64::from(padded_row) * u64::from(height),
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            copy_to_buffer(&mut enc, &frame.texture, &buffer, padded_row, width, height);
            buffer
        });
        self.renderer.queue.submit([enc.finish()]);
        if let Some(e) = popped_error(device) {
            return Err(RenderError::Gpu(e.to_string()));
        }
        let encode_ms = ms(t2);
        let t3 = Instant::now();
        frame.present();
        let picture = match (capture, readback) {
            (false, _) => Ok(None),
            (true, None) => self
                .renderer
                .render_to_rgba_with_hud(snap, screen, hud, width, height)
                .map(Some),
            (true, Some(buffer)) => read_buffer(
                device,
                &buffer,
                padded_row,
                width,
                height,
                self.config.format,
            )
            .map(Some),
        };
        self.last_times = DrawTimes {
            acquire_ms,
            build_ms,
            encode_ms,
            present_ms: ms(t3),
        };
        picture
    }
}

/// An sRGB 8-bit format if offered (the scene's colours assume sRGB encoding), else the
/// first offered.
fn choose_format(formats: &[wgpu::TextureFormat]) -> Option<wgpu::TextureFormat> {
    use wgpu::TextureFormat::{Bgra8UnormSrgb, Rgba8UnormSrgb};
    formats
        .iter()
        .copied()
        .find(|f| matches!(f, Bgra8UnormSrgb | Rgba8UnormSrgb))
        .or_else(|| formats.iter().copied().find(|f| f.is_srgb()))
        .or_else(|| formats.first().copied())
}

fn depth_texture(device: &wgpu::Device, width: u32, height: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("window depth"),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: DEPTH_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::unpad_rows;
    use wgpu::TextureFormat as F;

    #[test]
    fn prefers_srgb_formats() {
        assert_eq!(
            choose_format(&[F::Bgra8Unorm, F::Bgra8UnormSrgb]),
            Some(F::Bgra8UnormSrgb)
        );
        assert_eq!(
            choose_format(&[F::Rgb10a2Unorm, F::Rgba8UnormSrgb]),
            Some(F::Rgba8UnormSrgb)
        );
        assert_eq!(choose_format(&[F::Bgra8Unorm]), Some(F::Bgra8Unorm));
        assert_eq!(choose_format(&[]), None);
    }

    #[test]
    fn bgra_rows_are_swizzled_and_unpadded() {
        // Two pixels per row, rows padded to 12 bytes.
        let mapped = [
            1, 2, 3, 4, 5, 6, 7, 8, 0, 0, 0, 0, 9, 10, 11, 12, 13, 14, 15, 16, 0, 0, 0, 0,
        ];
        assert_eq!(
            unpad_rows(&mapped, 12, 2, F::Bgra8UnormSrgb),
            vec![3, 2, 1, 4, 7, 6, 5, 8, 11, 10, 9, 12, 15, 14, 13, 16]
        );
        assert_eq!(
            unpad_rows(&mapped, 12, 2, F::Rgba8UnormSrgb),
            vec![1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16]
        );
    }
}
