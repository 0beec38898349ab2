//! The renderer's bind group layouts, render pipelines and sampler: one shader module
//! (`shaders/scene.wgsl`), a pipeline per kind of thing drawn.

use crate::scene::{MeshInstance, Sprite, UiRect};
use bytemuck::{Pod, Zeroable};

/// The depth buffer's format.
pub(crate) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The nebula's texture format: sRGB storage keeps the dark gradients free of banding.
pub(crate) const NEBULA_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

/// A mesh vertex: position and normal in the mesh's frame.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct Vertex {
    pub(crate) pos: [f32; 3],
    pub(crate) normal: [f32; 3],
}
use wgpu::CompareFunction::{Always, Less, LessEqual};

/// Colour already multiplied by alpha, drawn over what is there.
const PREMULTIPLIED: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent::OVER,
};

/// Light added to what is there (stars, glows).
const ADDITIVE: wgpu::BlendState = wgpu::BlendState {
    color: wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    },
    alpha: wgpu::BlendComponent::OVER,
};

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];
const MESH_INSTANCE_ATTRIBUTES: [wgpu::VertexAttribute; 4] =
    wgpu::vertex_attr_array![2 => Float32x4, 3 => Float32x4, 4 => Float32x4, 5 => Float32x4];
const SPRITE_ATTRIBUTES: [wgpu::VertexAttribute; 3] =
    wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4];
const UI_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4];

/// A vertex buffer of `T`s, one a vertex or one an instance.
fn buffer_of<T>(
    step_mode: wgpu::VertexStepMode,
    attributes: &'static [wgpu::VertexAttribute],
) -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<T>() as u64,
        step_mode,
        attributes,
    }
}

/// How one pipeline draws: its shader entry points, buffers, blending and depth test.
struct Spec<'a> {
    label: &'a str,
    vs: &'a str,
    fs: &'a str,
    buffers: &'a [wgpu::VertexBufferLayout<'a>],
    blend: Option<wgpu::BlendState>,
    depth_write: bool,
    depth_compare: wgpu::CompareFunction,
    cull: Option<wgpu::Face>,
}

/// The bind group layouts, pipelines and sampler the renderer draws with.
pub(crate) struct Pipelines {
    /// The per-frame uniforms (group 0).
    pub(crate) bind_layout: wgpu::BindGroupLayout,
    /// The nebula texture and its sampler (group 1 of the sky).
    pub(crate) sky_layout: wgpu::BindGroupLayout,
    pub(crate) sampler: wgpu::Sampler,
    /// Renders the nebula into its low-resolution texture.
    pub(crate) nebula: wgpu::RenderPipeline,
    pub(crate) sky: wgpu::RenderPipeline,
    pub(crate) stars: wgpu::RenderPipeline,
    pub(crate) mesh: wgpu::RenderPipeline,
    pub(crate) shadow: wgpu::RenderPipeline,
    pub(crate) glow: wgpu::RenderPipeline,
    pub(crate) ui: wgpu::RenderPipeline,
}

impl Pipelines {
    /// Everything, for colour targets of `color_format`.
    pub(crate) fn new(device: &wgpu::Device, color_format: wgpu::TextureFormat) -> Self {
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../shaders/scene.wgsl").into()),
        });
        let (bind_layout, sky_layout) = bind_layouts(device);
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[&bind_layout],
            push_constant_ranges: &[],
        });
        let sky_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sky"),
            bind_group_layouts: &[&bind_layout, &sky_layout],
            push_constant_ranges: &[],
        });
        let vertices = buffer_of::<Vertex>(wgpu::VertexStepMode::Vertex, &VERTEX_ATTRIBUTES);
        let instance = wgpu::VertexStepMode::Instance;
        let meshes = buffer_of::<MeshInstance>(instance, &MESH_INSTANCE_ATTRIBUTES);
        let sprites = [buffer_of::<Sprite>(instance, &SPRITE_ATTRIBUTES)];
        let ui_rects = [buffer_of::<UiRect>(instance, &UI_ATTRIBUTES)];
        let pipeline = |layout: &wgpu::PipelineLayout, spec: Spec<'_>| {
            render_pipeline(device, &shader, color_format, layout, spec)
        };
        let over = |label, vs, fs, buffers, blend, depth_compare| Spec {
            label,
            vs,
            fs,
            buffers,
            blend: Some(blend),
            depth_write: false,
            depth_compare,
            cull: None,
        };
        Self {
            // The sky at the far plane: only where no mesh was drawn (depth still cleared).
            sky: pipeline(
                &sky_pipeline_layout,
                Spec {
                    blend: None,
                    ..over("sky", "vs_bg", "fs_sky", &[], ADDITIVE, LessEqual)
                },
            ),
            stars: pipeline(
                &layout,
                over("stars", "vs_star", "fs_star", &[], ADDITIVE, LessEqual),
            ),
            nebula: nebula_pipeline(device, &shader, &layout),
            mesh: pipeline(
                &layout,
                Spec {
                    label: "mesh",
                    vs: "vs_mesh",
                    fs: "fs_mesh",
                    buffers: &[vertices, meshes],
                    blend: None,
                    depth_write: true,
                    depth_compare: Less,
                    cull: Some(wgpu::Face::Back),
                },
            ),
            shadow: pipeline(
                &layout,
                over(
                    "shadow",
                    "vs_sprite",
                    "fs_sprite",
                    &sprites,
                    PREMULTIPLIED,
                    LessEqual,
                ),
            ),
            glow: pipeline(
                &layout,
                over(
                    "glow",
                    "vs_sprite",
                    "fs_sprite",
                    &sprites,
                    ADDITIVE,
                    LessEqual,
                ),
            ),
            ui: pipeline(
                &layout,
                over("ui", "vs_ui", "fs_ui", &ui_rects, PREMULTIPLIED, Always),
            ),
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("nebula"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                ..Default::default()
            }),
            bind_layout,
            sky_layout,
        }
    }
}

/// The per-frame uniforms' layout and the nebula texture's.
fn bind_layouts(device: &wgpu::Device) -> (wgpu::BindGroupLayout, wgpu::BindGroupLayout) {
    let globals = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("globals"),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    });
    let nebula = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("nebula texture"),
        entries: &[
            wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2,
                    multisampled: false,
                },
                count: None,
            },
            wgpu::BindGroupLayoutEntry {
                binding: 1,
                visibility: wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
        ],
    });
    (globals, nebula)
}

/// A pipeline drawing into the colour and depth targets as `spec` says.
fn render_pipeline(
    device: &wgpu::Device,
    shader: &wgpu::ShaderModule,
    color_format: wgpu::TextureFormat,
    layout: &wgpu::PipelineLayout,
    spec: Spec<'_>,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(spec.label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some(spec.vs),
            compilation_options: Default::default(),
            buffers: spec.buffers,
        },
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some(spec.fs),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: color_format,
                blend: spec.blend,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        primitive: wgpu::PrimitiveState {
            cull_mode: spec.cull,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: spec.depth_write,
            depth_compare: spec.depth_compare,
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        multiview: None,
        cache: None,
    })
}

/// The nebula, rendered into its own low-resolution texture (no depth).
fn nebula_pipeline(
    device: &wgpu::Device,
    shader: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("nebula"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some("vs_bg"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some("fs_nebula"),
            compilation_options: Default::default(),
            targets: &[Some(NEBULA_FORMAT.into())],
        }),
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        multiview: None,
        cache: None,
    })
}
