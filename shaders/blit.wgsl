// Copies the offscreen scene (sRGB-encoded Rgba8Unorm) into egui's render pass, whose viewport
// is the 3D view's rectangle. egui-wgpu renders to non-sRGB targets, so the bytes go through
// as they are; an sRGB target gets them decoded first (the hardware encodes them again).

@group(0) @binding(0) var scene: texture_2d<f32>;

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

// The target has the view's size in pixels: load the texel under the pixel (no filtering,
// no derivatives: cheapest on a software rasteriser).
fn texel(uv: vec2<f32>) -> vec4<f32> {
    let size = vec2<i32>(textureDimensions(scene));
    let p = clamp(vec2<i32>(uv * vec2<f32>(size)), vec2<i32>(0), size - vec2<i32>(1));
    return textureLoad(scene, p, 0);
}

@fragment
fn fs_copy(i: Out) -> @location(0) vec4<f32> {
    return texel(i.uv);
}

@fragment
fn fs_decode(i: Out) -> @location(0) vec4<f32> {
    let c = texel(i.uv);
    let lo = c.rgb / 12.92;
    let hi = pow((c.rgb + 0.055) / 1.055, vec3<f32>(2.4));
    return vec4<f32>(select(hi, lo, c.rgb <= vec3<f32>(0.04045)), c.a);
}
