// The page's mesh viewer (crate/src/web/viewer.rs): the generated mesh flat-shaded with its
// wireframe drawn over it in the same pass, and the input points as small screen-space squares.

struct View {
    // World to clip space.
    view_proj: mat4x4<f32>,
    // World-space direction towards the key light (above the viewer, to the left); w is 1
    // when a mesh is drawn (the points then take the overlay colour).
    light: vec4<f32>,
    // World-space direction towards the viewer (the fill light).
    eye: vec4<f32>,
    // Viewport width and height in pixels, point size in pixels, wireframe width in pixels.
    viewport: vec4<f32>,
}

@group(0) @binding(0) var<uniform> view: View;

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    // One corner of the triangle per vertex: (1,0,0), (0,1,0), (0,0,1).
    @location(1) barycentric: vec3<f32>,
}

// Triangles come unindexed, three vertices each, with the face normal on every vertex: flat
// shading shows the low-poly faces, and the barycentric corner gives the wireframe for free.
@vertex
fn mesh_vertex(
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @builtin(vertex_index) index: u32,
) -> MeshOut {
    var out: MeshOut;
    out.clip = view.view_proj * vec4<f32>(position, 1.0);
    out.normal = normal;
    let corner = index % 3u;
    out.barycentric = vec3<f32>(f32(corner == 0u), f32(corner == 1u), f32(corner == 2u));
    return out;
}

@fragment
fn mesh_fragment(in: MeshOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Two-sided: generated meshes can be open or inconsistently wound.
    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    // A key light from above and a dimmer fill from the eye over an ambient floor, so
    // differently turned facets (a dent, a fold) read apart.
    let light = 0.24 + 0.56 * max(dot(n, view.light.xyz), 0.0) + 0.2 * max(dot(n, view.eye.xyz), 0.0);
    let base = vec3<f32>(0.6, 0.76, 1.0) * light;
    // Distance to the nearest edge in pixels, from the barycentric's screen-space derivative.
    let d = in.barycentric / max(fwidth(in.barycentric), vec3<f32>(1e-6));
    let edge = min(min(d.x, d.y), d.z);
    let wire = 1.0 - smoothstep(0.0, view.viewport.w, edge);
    let color = mix(base, vec3<f32>(0.08, 0.12, 0.18), 0.85 * wire);
    return vec4<f32>(color, 1.0);
}

struct PointOut {
    @builtin(position) clip: vec4<f32>,
}

// One instance per input point, six vertices making a square of `viewport.z` pixels.
@vertex
fn point_vertex(@location(0) position: vec3<f32>, @builtin(vertex_index) index: u32) -> PointOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    var clip = view.view_proj * vec4<f32>(position, 1.0);
    let offset = corners[index] * view.viewport.z / view.viewport.xy;
    clip = vec4<f32>(clip.xy + offset * clip.w, clip.zw);
    var out: PointOut;
    out.clip = clip;
    return out;
}

@fragment
fn point_fragment() -> @location(0) vec4<f32> {
    // Blue alone, orange over a mesh (so the fit to them reads at a glance), as the 2D viewer.
    if (view.light.w > 0.5) {
        return vec4<f32>(0.88, 0.44, 0.1, 1.0);
    }
    return vec4<f32>(0.29, 0.44, 0.65, 1.0);
}
