//! The page's viewer shader (`shaders/viewer.wgsl`) validates, and each of its entry points
//! translates to GLSL ES 3.00, the language WebGL2 runs: wgpu's GL backend, which draws the
//! CPU path's viewer, goes through the same translation (naga) in the browser.

use naga::ShaderStage;
use naga::back::glsl;
use naga::valid::{Capabilities, ValidationFlags, Validator};

const SHADER: &str = include_str!("../../shaders/viewer.wgsl");

#[test]
fn the_viewer_shader_validates_and_translates_for_webgl2() {
    let module = naga::front::wgsl::parse_str(SHADER).expect("viewer.wgsl parses");
    let info = Validator::new(ValidationFlags::all(), Capabilities::empty())
        .validate(&module)
        .expect("viewer.wgsl validates with no optional capability");
    let options = glsl::Options {
        version: glsl::Version::new_gles(300),
        ..Default::default()
    };
    for (stage, entry) in [
        (ShaderStage::Vertex, "mesh_vertex"),
        (ShaderStage::Fragment, "mesh_fragment"),
        (ShaderStage::Vertex, "point_vertex"),
        (ShaderStage::Fragment, "point_fragment"),
    ] {
        let pipeline = glsl::PipelineOptions {
            shader_stage: stage,
            entry_point: entry.into(),
            multiview: None,
        };
        let mut out = String::new();
        glsl::Writer::new(
            &mut out,
            &module,
            &info,
            &options,
            &pipeline,
            naga::proc::BoundsCheckPolicies::default(),
        )
        .and_then(|mut writer| writer.write())
        .unwrap_or_else(|e| panic!("{entry}: no GLSL ES 3.00: {e}"));
        assert!(out.starts_with("#version 300 es"), "{entry}: {out}");
        assert!(out.contains("void main()"), "{entry}: {out}");
    }
}
