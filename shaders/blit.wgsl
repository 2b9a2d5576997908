// Copies the offscreen scene (sRGB-encoded Rgba8Unorm) into egui's render pass, whose viewport
// is the 3D view's rectangle. egui-wgpu renders to non-sRGB targets, so the bytes go through
// as they are; an sRGB target gets them decoded first (the hardware encodes them again).

@group(0) @binding(0) var scene: texture_2d<f32>;
@group(0) @binding(1) var scene_sampler: sampler;

struct Out {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_full(@builtin(vertex_index) vi: u32) -> Out {
    // One triangle covering the viewport.
    let x = f32((vi << 1u) & 2u);
    let y = f32(vi & 2u);
    var o: Out;
    o.clip = vec4<f32>(x * 2.0 - 1.0, 1.0 - y * 2.0, 0.0, 1.0);
    o.uv = vec2<f32>(x, y);
    return o;
}

@fragment
fn fs_copy(i: Out) -> @location(0) vec4<f32> {
    return textureSample(scene, scene_sampler, i.uv);
}

@fragment
fn fs_decode(i: Out) -> @location(0) vec4<f32> {
    let c = textureSample(scene, scene_sampler, i.uv);
    let lo = c.rgb / 12.92;
    let hi = pow((c.rgb + 0.055) / 1.055, vec3<f32>(2.4));
    return vec4<f32>(select(hi, lo, c.rgb <= vec3<f32>(0.04045)), c.a);
}
