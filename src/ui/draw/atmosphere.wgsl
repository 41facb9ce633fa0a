// The Earth's atmosphere: a ring around the planet's silhouette, turned to
// face the camera, glowing at the limb on the side the sun lights. Only the
// rim's pixels are drawn (a shell around the whole planet would shade the
// whole disc again).
#import bevy_pbr::forward_io::VertexOutput

struct Atmosphere {
    // Linear RGB, and the glow's strength in alpha.
    color: vec4<f32>,
    // Direction towards the sun (xyz).
    sun: vec4<f32>,
};

@group(#{MATERIAL_BIND_GROUP}) @binding(0) var<uniform> atmosphere: Atmosphere;

@fragment
fn fragment(in: VertexOutput) -> @location(0) vec4<f32> {
    // uv.x: distance from the center in silhouette radii; the normal points
    // outwards from the center, in the ring's plane.
    let t = in.uv.x;
    var glow = 1.0 - smoothstep(1.0, 1.07, t);
    glow = glow * glow;
    if (t < 1.0) {
        glow = 0.7 * smoothstep(0.93, 1.0, t);
    }
    let day = smoothstep(-0.35, 0.35, dot(normalize(in.world_normal), atmosphere.sun.xyz));
    let alpha = clamp(glow * (0.1 + 0.9 * day) * atmosphere.color.a, 0.0, 1.0);
    return vec4<f32>(atmosphere.color.rgb, alpha);
}
