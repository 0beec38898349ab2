//! The wgpu renderer: device, pipelines and offscreen frames.

use crate::image::RgbaImage;
use crate::scene::{self, Hud, Scene, Screen};
use crate::view::FrameSnapshot;
use crate::RenderError;
use bytemuck::{Pod, Zeroable};
use wgpu::util::DeviceExt;

mod device;
mod pipelines;
mod readback;

pub(crate) use pipelines::DEPTH_FORMAT;
use pipelines::{Vertex, NEBULA_FORMAT};

#[cfg(target_arch = "wasm32")]
pub(crate) use device::new_browser_instance;
pub(crate) use device::{new_instance, open_device, open_device_async, popped_error};
#[cfg(test)]
pub(crate) use readback::unpad_rows;
pub(crate) use readback::{copy_to_buffer, padded_row_bytes, read_buffer};

/// The colour format of offscreen pictures (a window uses its surface's format).
pub(crate) const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// The nebula is drawn at `1 / NEBULA_DOWNSCALE` of the frame's width and height and
/// filtered up (`fs_nebula` in `scene.wgsl`).
const NEBULA_DOWNSCALE: u32 = 4;
/// Sphere meshes, (rings, segments): the ball's, and the small parts' (helmets, pads;
/// a few pixels across, where triangle setup is the cost on a software rasteriser).
const BALL_SPHERE: (u32, u32) = (14, 24);
const SMALL_SPHERE: (u32, u32) = (8, 14);

/// Largest offscreen image side, pixels.
pub const MAX_SIDE: u32 = 8192;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    cam_right: [f32; 4],
    cam_up: [f32; 4],
    eye: [f32; 4],
    light_dir: [f32; 4],
    screen: [f32; 4],
    star_cols: [f32; 4],
    star_rows: [f32; 4],
}

/// The star layers' cell grids over a `width × height` frame (`vs_star` in
/// `scene.wgsl`): per layer the columns and rows of cells drawn, and the instances in
/// all. The sky is 720 units high; layer `k` has cells of `46 − 14k` units drifting
/// left, so the columns span the width plus the cell entering, and one cell beyond every
/// edge (a star's glow reaches a few units past its cell).
pub(crate) fn star_grid(width: u32, height: u32) -> ([f32; 3], [f32; 3], u32) {
    let w_units = 720.0 * width as f32 / height.max(1) as f32;
    let mut cols = [0.0; 3];
    let mut rows = [0.0; 3];
    let mut total = 0;
    for k in 0..3 {
        let cell = 46.0 - 14.0 * k as f32;
        cols[k] = (w_units / cell).ceil() + 3.0;
        rows[k] = (720.0 / cell).ceil() + 3.0;
        total += (cols[k] * rows[k]) as u32;
    }
    (cols, rows, total)
}

struct Mesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    count: u32,
}

/// The nebula's low-resolution picture for frames of `width × height`.
struct NebulaTarget {
    width: u32,
    height: u32,
    view: wgpu::TextureView,
    bind: wgpu::BindGroup,
}

struct Target {
    width: u32,
    height: u32,
    color: wgpu::Texture,
    depth: wgpu::Texture,
    readback: wgpu::Buffer,
    padded_row: u32,
}

/// Which adapter renders, in words (name and backend).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AdapterSummary {
    /// Adapter name, e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`.
    pub name: String,
    /// Backend, e.g. `Vulkan`.
    pub backend: String,
    /// Device type, e.g. `Cpu`.
    pub device_type: String,
}

/// An offscreen renderer on whatever adapter exists. Create once, render many frames.
pub struct Renderer {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    adapter: AdapterSummary,
    color_format: wgpu::TextureFormat,
    /// The bind group layouts, the pipelines and the sampler.
    pipes: pipelines::Pipelines,
    cube: Mesh,
    sphere: Mesh,
    small_sphere: Mesh,
    nebula_target: Option<NebulaTarget>,
    target: Option<Target>,
}

impl Renderer {
    /// Opens the first adapter available (a hardware GPU, else a fallback/software one
    /// such as Mesa's lavapipe). No adapter at all is [`RenderError::NoAdapter`].
    pub fn new() -> Result<Renderer, RenderError> {
        let instance = new_instance();
        let (adapter, device, queue) = open_device(&instance, None)?;
        Self::with_device(&adapter, device, queue, COLOR_FORMAT)
    }

    /// Builds the pipelines on an open device for colour targets of `color_format`.
    pub(crate) fn with_device(
        adapter: &wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
        color_format: wgpu::TextureFormat,
    ) -> Result<Renderer, RenderError> {
        let info = adapter.get_info();
        let adapter_summary = AdapterSummary {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend),
            device_type: format!("{:?}", info.device_type),
        };
        device.push_error_scope(wgpu::ErrorFilter::Validation);
        let r = Self::build(device, queue, adapter_summary, color_format);
        if let Some(e) = popped_error(&r.device) {
            return Err(RenderError::Gpu(e.to_string()));
        }
        Ok(r)
    }

    fn build(
        device: wgpu::Device,
        queue: wgpu::Queue,
        adapter: AdapterSummary,
        color_format: wgpu::TextureFormat,
    ) -> Renderer {
        let pipes = pipelines::Pipelines::new(&device, color_format);
        let (cv, ci) = cube_mesh();
        let (sv, si) = sphere_mesh(BALL_SPHERE.0, BALL_SPHERE.1);
        let (pv, pi) = sphere_mesh(SMALL_SPHERE.0, SMALL_SPHERE.1);
        let cube = upload_mesh(&device, &cv, &ci);
        let sphere = upload_mesh(&device, &sv, &si);
        let small_sphere = upload_mesh(&device, &pv, &pi);
        Renderer {
            device,
            queue,
            adapter,
            color_format,
            pipes,
            cube,
            sphere,
            small_sphere,
            nebula_target: None,
            target: None,
        }
    }

    /// The adapter in use.
    pub fn adapter(&self) -> &AdapterSummary {
        &self.adapter
    }

    fn ensure_target(&mut self, width: u32, height: u32) -> Result<(), RenderError> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(RenderError::BadSize {
                width,
                height,
                max: MAX_SIDE,
            });
        }
        if matches!(&self.target, Some(t) if t.width == width && t.height == height) {
            return Ok(());
        }
        let size = wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        };
        let tex = |label, format, usage| {
            self.device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let color = tex(
            "color",
            self.color_format,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let depth = tex(
            "depth",
            DEPTH_FORMAT,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        );
        let padded_row = padded_row_bytes(width);
        let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: padded_row as u64 * height as u64,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        self.target = Some(Target {
            width,
            height,
            color,
            depth,
            readback,
            padded_row,
        });
        Ok(())
    }

    /// Renders a frame offscreen and waits for the GPU to finish it (no read back).
    pub fn render(
        &mut self,
        snap: &FrameSnapshot,
        screen: Screen,
        width: u32,
        height: u32,
    ) -> Result<(), RenderError> {
        self.frame(snap, screen, &Hud::default(), width, height, false)
    }

    /// Renders a frame offscreen and reads it back as an RGBA image (sRGB bytes).
    pub fn render_to_rgba(
        &mut self,
        snap: &FrameSnapshot,
        screen: Screen,
        width: u32,
        height: u32,
    ) -> Result<RgbaImage, RenderError> {
        self.render_to_rgba_with_hud(snap, screen, &Hud::default(), width, height)
    }

    /// [`Renderer::render_to_rgba`] with the live text `hud` over the screen.
    pub fn render_to_rgba_with_hud(
        &mut self,
        snap: &FrameSnapshot,
        screen: Screen,
        hud: &Hud,
        width: u32,
        height: u32,
    ) -> Result<RgbaImage, RenderError> {
        self.frame(snap, screen, hud, width, height, true)?;
        self.read_back()
    }

    fn frame(
        &mut self,
        snap: &FrameSnapshot,
        screen: Screen,
        hud: &Hud,
        width: u32,
        height: u32,
        copy: bool,
    ) -> Result<(), RenderError> {
        self.ensure_target(width, height)?;
        let scene = scene::build_with_hud(snap, screen, hud, width, height);
        self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        self.encode(&scene, width, height, copy);
        if let Some(e) = pollster::block_on(self.device.pop_error_scope()) {
            return Err(RenderError::Gpu(e.to_string()));
        }
        self.device
            .poll(wgpu::PollType::Wait)
            .map_err(|e| RenderError::Gpu(e.to_string()))?;
        Ok(())
    }

    fn encode(&mut self, scene: &Scene, width: u32, height: u32, copy: bool) {
        let Some(target) = &self.target else { return };
        let color_view = target.color.create_view(&Default::default());
        let depth_view = target.depth.create_view(&Default::default());
        let mut enc = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.encode_scene(&mut enc, scene, &color_view, &depth_view, width, height);
        let Some(target) = &self.target else { return };
        if copy {
            copy_to_buffer(
                &mut enc,
                &target.color,
                &target.readback,
                target.padded_row,
                width,
                height,
            );
        }
        self.queue.submit([enc.finish()]);
    }

    /// Records the render pass drawing `scene` into `color_view` (of this renderer's
    /// colour format) with `depth_view` (depth format, same size `width × height`).
    pub(crate) fn encode_scene(
        &mut self,
        enc: &mut wgpu::CommandEncoder,
        scene: &Scene,
        color_view: &wgpu::TextureView,
        depth_view: &wgpu::TextureView,
        width: u32,
        height: u32,
    ) {
        let cam = &scene.camera;
        let light = glam::Vec3::new(-0.35, -0.55, 0.9).normalize();
        let (star_cols, star_rows, star_cells) = star_grid(width, height);
        let globals = Globals {
            view_proj: cam.view_proj.to_cols_array_2d(),
            cam_right: cam.right.extend(0.0).to_array(),
            cam_up: cam.up.extend(0.0).to_array(),
            eye: cam.eye.extend(1.0).to_array(),
            light_dir: light.extend(0.0).to_array(),
            screen: [
                width as f32,
                height as f32,
                scene.time_s,
                NEBULA_DOWNSCALE as f32,
            ],
            star_cols: [star_cols[0], star_cols[1], star_cols[2], 0.0],
            star_rows: [star_rows[0], star_rows[1], star_rows[2], 0.0],
        };
        self.ensure_nebula_target(width, height);
        let d = &self.device;
        let uniform = d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("globals"),
            contents: bytemuck::bytes_of(&globals),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let bind = d.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &self.pipes.bind_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: uniform.as_entire_binding(),
            }],
        });
        let instances = |label: &str, bytes: &[u8]| {
            (!bytes.is_empty()).then(|| {
                d.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents: bytes,
                    usage: wgpu::BufferUsages::VERTEX,
                })
            })
        };
        let boxes = instances("boxes", bytemuck::cast_slice(&scene.boxes));
        let spheres = instances("spheres", bytemuck::cast_slice(&scene.spheres));
        let small_spheres = instances("small spheres", bytemuck::cast_slice(&scene.small_spheres));
        let shadows = instances("shadows", bytemuck::cast_slice(&scene.shadows));
        let particles = instances("particles", bytemuck::cast_slice(&scene.particles));
        let ui = instances("ui", bytemuck::cast_slice(&scene.ui));

        let Some(nebula) = &self.nebula_target else {
            return;
        };
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("nebula"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: &nebula.view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: None,
                timestamp_writes: None,
                occlusion_query_set: None,
            });
            pass.set_bind_group(0, &bind, &[]);
            pass.set_pipeline(&self.pipes.nebula);
            pass.draw(0..3, 0..1);
        }
        {
            let mut pass = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: color_view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Discard,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
            });
            pass.set_bind_group(0, &bind, &[]);
            pass.set_pipeline(&self.pipes.mesh);
            for (mesh, buf, n) in [
                (&self.cube, &boxes, scene.boxes.len()),
                (&self.sphere, &spheres, scene.spheres.len()),
                (
                    &self.small_sphere,
                    &small_spheres,
                    scene.small_spheres.len(),
                ),
            ] {
                if let Some(buf) = buf {
                    pass.set_vertex_buffer(0, mesh.vertices.slice(..));
                    pass.set_vertex_buffer(1, buf.slice(..));
                    pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                    pass.draw_indexed(0..mesh.count, 0, 0..n as u32);
                }
            }
            // The sky after the opaque meshes: the depth test skips the covered pixels.
            pass.set_pipeline(&self.pipes.sky);
            pass.set_bind_group(1, &nebula.bind, &[]);
            pass.draw(0..3, 0..1);
            pass.set_pipeline(&self.pipes.stars);
            pass.draw(0..6, 0..star_cells);
            for (pipeline, buf, n) in [
                (&self.pipes.shadow, &shadows, scene.shadows.len()),
                (&self.pipes.glow, &particles, scene.particles.len()),
                (&self.pipes.ui, &ui, scene.ui.len()),
            ] {
                if let Some(buf) = buf {
                    pass.set_pipeline(pipeline);
                    pass.set_vertex_buffer(0, buf.slice(..));
                    pass.draw(0..6, 0..n as u32);
                }
            }
        }
    }

    /// Makes the nebula's low-resolution texture match frames of `width × height`.
    fn ensure_nebula_target(&mut self, width: u32, height: u32) {
        if matches!(&self.nebula_target, Some(n) if n.width == width && n.height == height) {
            return;
        }
        let texture = self.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("nebula"),
            size: wgpu::Extent3d {
                width: width.div_ceil(NEBULA_DOWNSCALE).max(1),
                height: height.div_ceil(NEBULA_DOWNSCALE).max(1),
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: NEBULA_FORMAT,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        });
        let view = texture.create_view(&Default::default());
        let bind = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("nebula texture"),
            layout: &self.pipes.sky_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&self.pipes.sampler),
                },
            ],
        });
        self.nebula_target = Some(NebulaTarget {
            width,
            height,
            view,
            bind,
        });
    }

    fn read_back(&self) -> Result<RgbaImage, RenderError> {
        let Some(target) = &self.target else {
            return Err(RenderError::Gpu("no render target".into()));
        };
        read_buffer(
            &self.device,
            &target.readback,
            target.padded_row,
            target.width,
            target.height,
            self.color_format,
        )
    }

    /// The colour format pictures are drawn in.
    pub fn color_format(&self) -> wgpu::TextureFormat {
        self.color_format
    }
}

fn upload_mesh(device: &wgpu::Device, v: &[Vertex], i: &[u32]) -> Mesh {
    Mesh {
        vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mesh vertices"),
            contents: bytemuck::cast_slice(v),
            usage: wgpu::BufferUsages::VERTEX,
        }),
        indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mesh indices"),
            contents: bytemuck::cast_slice(i),
            usage: wgpu::BufferUsages::INDEX,
        }),
        count: i.len() as u32,
    }
}

/// The unit cube `[-1, 1]³`, 4 vertices per face (flat normals), counter-clockwise.
fn cube_mesh() -> (Vec<Vertex>, Vec<u32>) {
    let mut v = Vec::new();
    let mut idx = Vec::new();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = [0.0; 3];
            n[axis] = sign;
            let u = (axis + 1) % 3;
            let w = (axis + 2) % 3;
            let base = v.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = [0.0; 3];
                p[axis] = sign;
                p[u] = a;
                p[w] = b;
                v.push(Vertex { pos: p, normal: n });
            }
            // (u, w, axis) is right-handed: counter-clockwise seen from +axis.
            if sign > 0.0 {
                idx.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            } else {
                idx.extend([base, base + 2, base + 1, base, base + 3, base + 2]);
            }
        }
    }
    (v, idx)
}

/// The unit sphere as a latitude/longitude mesh.
fn sphere_mesh(rings: u32, segments: u32) -> (Vec<Vertex>, Vec<u32>) {
    let mut v = Vec::new();
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            let p = [
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ];
            v.push(Vertex { pos: p, normal: p });
        }
    }
    let mut idx = Vec::new();
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let a = r * row + s;
            let b = a + row;
            idx.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
    (v, idx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn star_grids_cover_the_frame_with_a_cell_to_spare() {
        for (w, h) in [(1280, 720), (640, 360), (1920, 1080), (720, 1280), (1, 1)] {
            let (cols, rows, total) = star_grid(w, h);
            let w_units = 720.0 * w as f32 / h as f32;
            let mut sum = 0;
            for k in 0..3 {
                let cell = 46.0 - 14.0 * k as f32;
                // A drifting window of the width spans at most ceil(W / cell) + 1 cells.
                assert!(
                    (cols[k] - 2.0) * cell >= w_units + cell,
                    "{w}x{h} layer {k}"
                );
                assert!((rows[k] - 2.0) * cell >= 720.0, "{w}x{h} layer {k}");
                sum += (cols[k] * rows[k]) as u32;
            }
            assert_eq!(sum, total);
        }
    }

    #[test]
    fn cube_faces_wind_outwards() {
        let (v, i) = cube_mesh();
        for t in i.chunks(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|k| glam::Vec3::from(v[k as usize].pos));
            let n = glam::Vec3::from(v[t[0] as usize].normal);
            assert!((b - a).cross(c - a).dot(n) > 0.0);
        }
    }

    #[test]
    fn sphere_faces_wind_outwards() {
        let (v, i) = sphere_mesh(6, 8);
        for t in i.chunks(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|k| glam::Vec3::from(v[k as usize].pos));
            let area = (b - a).cross(c - a);
            if area.length() > 1e-6 {
                assert!(area.dot(a + b + c) > 0.0);
            }
        }
    }
}
