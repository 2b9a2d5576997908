//! What ringlab's wgpu pipelines share, written once: a WGSL module, bind-group layouts numbered
//! in order, one-sample render pipelines with at most one colour target (the scene's, the
//! blit's, the lean painter's: none uses MSAA, so edges do not depend on a driver), and a paint
//! callback that hands its work to a resource kept in egui-wgpu's callback resources.

use eframe::egui;
use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, ScreenDescriptor};
use std::num::NonZeroU64;

/// A WGSL module.
pub(super) fn shader(device: &wgpu::Device, label: &str, wgsl: &'static str) -> wgpu::ShaderModule {
    device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(label),
        source: wgpu::ShaderSource::Wgsl(wgsl.into()),
    })
}

/// A bind-group layout whose entries are bound at 0, 1, ... in the order given.
pub(super) fn bind_group_layout(
    device: &wgpu::Device,
    label: &str,
    entries: &[(wgpu::ShaderStages, wgpu::BindingType)],
) -> wgpu::BindGroupLayout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = entries
        .iter()
        .enumerate()
        .map(|(i, &(visibility, ty))| wgpu::BindGroupLayoutEntry {
            binding: i as u32,
            visibility,
            ty,
            count: None,
        })
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// A uniform buffer of at least `min_size` bytes (0: not checked), at a dynamic offset or not.
pub(super) fn uniform(dynamic: bool, min_size: u64) -> wgpu::BindingType {
    wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: dynamic,
        min_binding_size: NonZeroU64::new(min_size),
    }
}

/// A 2D texture, not multisampled.
pub(super) fn texture(sample_type: wgpu::TextureSampleType) -> wgpu::BindingType {
    wgpu::BindingType::Texture {
        sample_type,
        view_dimension: wgpu::TextureViewDimension::D2,
        multisampled: false,
    }
}

/// A pipeline layout of these bind groups, in order, without immediates.
pub(super) fn pipeline_layout(
    device: &wgpu::Device,
    label: &str,
    groups: &[&wgpu::BindGroupLayout],
) -> wgpu::PipelineLayout {
    let groups: Vec<Option<&wgpu::BindGroupLayout>> = groups.iter().copied().map(Some).collect();
    device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(label),
        bind_group_layouts: &groups,
        immediate_size: 0,
    })
}

/// A colour target writing every channel.
pub(super) fn color_target(
    format: wgpu::TextureFormat,
    blend: Option<wgpu::BlendState>,
) -> wgpu::ColorTargetState {
    wgpu::ColorTargetState { format, blend, write_mask: wgpu::ColorWrites::ALL }
}

/// One render pipeline: one sample, triangles, one shader module for both stages.
pub(super) struct PipelineSpec<'a> {
    pub label: &'a str,
    pub layout: &'a wgpu::PipelineLayout,
    pub shader: &'a wgpu::ShaderModule,
    /// The vertex entry point and its vertex buffers.
    pub vertex: &'a str,
    pub buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    pub cull: Option<wgpu::Face>,
    pub depth: Option<wgpu::DepthStencilState>,
    /// The fragment entry point and its colour target; None: depth only.
    pub fragment: Option<(&'a str, wgpu::ColorTargetState)>,
}

impl PipelineSpec<'_> {
    pub fn build(&self, device: &wgpu::Device) -> wgpu::RenderPipeline {
        let targets = [self.fragment.as_ref().map(|(_, target)| target.clone())];
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(self.label),
            layout: Some(self.layout),
            vertex: wgpu::VertexState {
                module: self.shader,
                entry_point: Some(self.vertex),
                compilation_options: Default::default(),
                buffers: self.buffers,
            },
            primitive: wgpu::PrimitiveState { cull_mode: self.cull, ..Default::default() },
            depth_stencil: self.depth.clone(),
            multisample: wgpu::MultisampleState::default(),
            fragment: self.fragment.as_ref().map(|(entry, _)| wgpu::FragmentState {
                module: self.shader,
                entry_point: Some(*entry),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// A paint callback's work, done by the resource of type `Resource` that egui-wgpu's callback
/// resources hold (put there once, by `callback::install`); nothing is drawn without it.
pub trait ResourcePaint: Send + Sync + 'static {
    type Resource: Send + Sync + 'static;

    /// Before egui's render pass: uploads, and passes of its own on egui's encoder.
    fn prepare(
        &self,
        resource: &mut Self::Resource,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
    );

    /// Inside egui's render pass.
    fn paint(
        &self,
        resource: &Self::Resource,
        info: &egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
    );
}

/// The paint callback over `rect` (points) that does `work`.
pub fn resource_callback<P: ResourcePaint>(rect: egui::Rect, work: P) -> egui::PaintCallback {
    egui_wgpu::Callback::new_paint_callback(rect, WithResource(work))
}

struct WithResource<P>(P);

impl<P: ResourcePaint> CallbackTrait for WithResource<P> {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(r) = resources.get_mut::<P::Resource>() {
            self.0.prepare(r, device, queue, screen, encoder);
        }
        Vec::new()
    }

    fn paint(
        &self,
        info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        if let Some(r) = resources.get::<P::Resource>() {
            self.0.paint(r, &info, pass);
        }
    }
}
