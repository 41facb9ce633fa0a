// Body cubes drawn in one instanced draw: a unit cube mesh, moved and sized
// per instance, lit by the sun from a fixed direction plus an ambient term.
#import bevy_pbr::mesh_view_bindings::view

struct Vertex {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    // Per instance: center, half extents, color (sRGB bytes, unpacked to 0..1).
    @location(3) i_center: vec3<f32>,
    @location(4) i_half: vec3<f32>,
    @location(5) i_color: vec4<f32>,
};

struct VertexOutput {
    @builtin(position) clip_position: vec4<f32>,
    @location(0) color: vec4<f32>,
};

// The least a body's largest half-extent takes on screen, in pixels: a body
// far away is drawn grown to this (2.5 px across), never as a sub-pixel
// dot, so a cloud reads as a cloud at every zoom and stands out from the
// stars (drawn smaller and dimmer, backdrop.rs).
const MIN_HALF_PIXELS: f32 = 1.25;

// Direction towards the sun; matches the scene's directional light.
const SUN: vec3<f32> = vec3<f32>(0.5773503, 0.5773503, 0.5773503);

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
}

@vertex
fn vertex(vertex: Vertex) -> VertexOutput {
    // The body's largest half-extent in pixels at its depth: the
    // projection's vertical scale over w (1 for an orthographic one), times
    // half the viewport's height.
    let center = view.clip_from_world * vec4<f32>(vertex.i_center, 1.0);
    let half = max(max(vertex.i_half.x, vertex.i_half.y), vertex.i_half.z);
    let pixels = half * view.clip_from_view[1][1] * 0.5 * view.viewport.w / max(abs(center.w), 1e-6);
    let grow = clamp(MIN_HALF_PIXELS / max(pixels, 1e-9), 1.0, 1e4);
    // The mesh is a cube of edge 1: scale by the full extents (grown).
    let world = vertex.i_center + vertex.position * 2.0 * vertex.i_half * grow;
    var out: VertexOutput;
    out.clip_position = view.clip_from_world * vec4<f32>(world, 1.0);
    let diffuse = max(dot(vertex.normal, SUN), 0.0);
    let light = 0.3 + 0.7 * diffuse;
    out.color = vec4<f32>(srgb_to_linear(vertex.i_color.rgb) * light, 1.0);
    return out;
}

@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    return in.color;
}
