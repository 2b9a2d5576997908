//! The scene's pipelines and bind-group layouts (one WGSL module, `shaders/scene.wgsl`), and
//! the copy of the finished scene into egui's render pass (`shaders/blit.wgsl`).

use super::kit;
use super::mesh::Vertex;
use super::scene::TraceSegment;

/// The offscreen colour format: 8-bit, holding the sRGB-encoded values the shaders write (an
/// sRGB view that encodes on write measured slower on lavapipe than the shaders' own cheap
/// encoding).
pub const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
pub(super) const DRAW_FORMAT: wgpu::TextureFormat = COLOR_FORMAT;
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Size of one object's uniforms in the shader (model matrix, colour, material).
pub(super) const OBJECT_SIZE: u64 = 96;

pub(super) struct Pipelines {
    pub body: wgpu::RenderPipeline,
    pub table: wgpu::RenderPipeline,
    pub trace: wgpu::RenderPipeline,
    pub shade: wgpu::RenderPipeline,
    pub shadow: wgpu::RenderPipeline,
    pub globals_layout: wgpu::BindGroupLayout,
    pub objects_layout: wgpu::BindGroupLayout,
    /// The shadow map and its comparison sampler.
    pub textures_layout: wgpu::BindGroupLayout,
}

impl Pipelines {
    /// `globals_size`: the size of the per-view uniforms.
    pub fn new(device: &wgpu::Device, globals_size: u64) -> Pipelines {
        let shader = kit::shader(device, "scene.wgsl", include_str!("../../shaders/scene.wgsl"));
        let both = wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT;
        let frag = wgpu::ShaderStages::FRAGMENT;
        let globals_layout =
            kit::bind_group_layout(device, "globals", &[(both, kit::uniform(false, globals_size))]);
        let objects_layout =
            kit::bind_group_layout(device, "object", &[(both, kit::uniform(true, OBJECT_SIZE))]);
        let textures_layout = kit::bind_group_layout(
            device,
            "shadow map",
            &[
                (frag, kit::texture(wgpu::TextureSampleType::Depth)),
                (frag, wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison)),
            ],
        );
        let main_layout = kit::pipeline_layout(
            device,
            "scene",
            &[&globals_layout, &objects_layout, &textures_layout],
        );
        let shadow_layout =
            kit::pipeline_layout(device, "shadow", &[&globals_layout, &objects_layout]);

        let vertex_layout = [Some(wgpu::VertexBufferLayout {
            array_stride: size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4],
        })];
        let trace_layout = [Some(wgpu::VertexBufferLayout {
            array_stride: size_of::<TraceSegment>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x2],
        })];
        let depth = |write: bool, bias: wgpu::DepthBiasState| wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(write),
            depth_compare: Some(wgpu::CompareFunction::LessEqual),
            stencil: wgpu::StencilState::default(),
            bias,
        };
        let towards_eye = wgpu::DepthBiasState { constant: -4, slope_scale: -2.0, clamp: 0.0 };
        // A pipeline of the scene's layout, culling nothing.
        let scene = |label, vertex, buffers, fragment, depth| kit::PipelineSpec {
            label,
            layout: &main_layout,
            shader: &shader,
            vertex,
            buffers,
            cull: None,
            depth: Some(depth),
            fragment: Some(fragment),
        };
        let opaque = kit::color_target(DRAW_FORMAT, None);
        let mesh_depth = depth(true, wgpu::DepthBiasState::default());
        let body = kit::PipelineSpec {
            cull: Some(wgpu::Face::Back),
            ..scene(
                "bodies",
                "vs_mesh",
                &vertex_layout,
                ("fs_body", opaque.clone()),
                mesh_depth.clone(),
            )
        }
        .build(device);
        let table = scene("table", "vs_mesh", &vertex_layout, ("fs_table", opaque), mesh_depth)
            .build(device);
        // Traces lie on the table: drawn after it with a depth bias towards the eye, so they
        // win against the table at any distance yet still hide behind a body.
        let blended = kit::color_target(DRAW_FORMAT, Some(wgpu::BlendState::ALPHA_BLENDING));
        let trace = scene(
            "traces",
            "vs_trace",
            &trace_layout,
            ("fs_trace", blended),
            depth(false, towards_eye),
        )
        .build(device);
        // Shadow and contact shading of the table near the bodies: multiplies what the table
        // and the traces left (blend: source times destination), before the bodies are drawn.
        let multiply = kit::color_target(
            DRAW_FORMAT,
            Some(wgpu::BlendState {
                color: wgpu::BlendComponent {
                    src_factor: wgpu::BlendFactor::Dst,
                    dst_factor: wgpu::BlendFactor::Zero,
                    operation: wgpu::BlendOperation::Add,
                },
                alpha: wgpu::BlendComponent {
                    src_factor: wgpu::BlendFactor::Zero,
                    dst_factor: wgpu::BlendFactor::One,
                    operation: wgpu::BlendOperation::Add,
                },
            }),
        );
        let shade = scene(
            "table shading",
            "vs_shade",
            &[],
            ("fs_shade", multiply),
            depth(false, towards_eye),
        )
        .build(device);
        let shadow = kit::PipelineSpec {
            label: "shadow",
            layout: &shadow_layout,
            shader: &shader,
            vertex: "vs_shadow",
            buffers: &vertex_layout,
            cull: None,
            depth: Some(depth(
                true,
                wgpu::DepthBiasState { constant: 2, slope_scale: 2.0, clamp: 0.0 },
            )),
            fragment: None,
        }
        .build(device);

        Pipelines {
            body,
            table,
            trace,
            shade,
            shadow,
            globals_layout,
            objects_layout,
            textures_layout,
        }
    }
}

/// Copies the offscreen scene into the render pass it is given (egui's, in the window).
pub(super) struct Blit {
    pub pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
}

impl Blit {
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Blit {
        let shader = kit::shader(device, "blit.wgsl", include_str!("../../shaders/blit.wgsl"));
        let texture = kit::texture(wgpu::TextureSampleType::Float { filterable: false });
        let layout =
            kit::bind_group_layout(device, "blit", &[(wgpu::ShaderStages::FRAGMENT, texture)]);
        let pipeline = kit::PipelineSpec {
            label: "blit",
            layout: &kit::pipeline_layout(device, "blit", &[&layout]),
            shader: &shader,
            vertex: "vs_full",
            buffers: &[],
            cull: None,
            depth: None,
            fragment: Some((
                if format.is_srgb() { "fs_decode" } else { "fs_copy" },
                kit::color_target(format, None),
            )),
        }
        .build(device);
        Blit { pipeline, layout }
    }

    pub fn group(&self, device: &wgpu::Device, view: &wgpu::TextureView) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("blit"),
            layout: &self.layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::TextureView(view),
            }],
        })
    }
}
