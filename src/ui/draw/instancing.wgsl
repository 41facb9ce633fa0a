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

// Direction towards the sun; matches the scene's directional light.
const SUN: vec3<f32> = vec3<f32>(0.5773503, 0.5773503, 0.5773503);

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    return select(pow((c + 0.055) / 1.055, vec3<f32>(2.4)), c / 12.92, c <= vec3<f32>(0.04045));
}

@vertex
fn vertex(vertex: Vertex) -> VertexOutput {
    // The mesh is a cube of edge 1: scale by the full extents.
    let world = vertex.i_center + vertex.position * 2.0 * vertex.i_half;
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
