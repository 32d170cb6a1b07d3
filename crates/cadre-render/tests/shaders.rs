//! Every pass's WGSL parses and validates with naga (the compiler wgpu uses), and the structs
//! shared with Rust have the sizes of their `cadre_render::layout` twins.

use std::path::Path;

use cadre_render::SECTION_CAP;
use cadre_render::layout::{
    DRAW_CLOSED, DRAW_INSIDE_OUT, Draw, Frame, LightGpu, Material, Segment,
};

/// Parses and validates one shader; returns the module.
fn module(pass: &str) -> naga::Module {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("src/passes")
        .join(pass)
        .join(format!("{pass}.wgsl"));
    // Passes are built as the shared declarations followed by their own source.
    let common = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/passes/common.wgsl");
    let source = std::fs::read_to_string(&common).expect("common.wgsl")
        + "\n"
        + &std::fs::read_to_string(&path).expect("shader source");
    let module = naga::front::wgsl::parse_str(&source)
        .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{}: {e:?}", path.display()));
    module
}

/// The value of the `u32` constant `name` of `module`.
fn constant_u32(module: &naga::Module, name: &str) -> Option<u32> {
    let c = module
        .constants
        .iter()
        .find(|(_, c)| c.name.as_deref() == Some(name))?
        .1;
    match module.global_expressions[c.init] {
        naga::Expression::Literal(naga::Literal::U32(v)) => Some(v),
        _ => None,
    }
}

/// Size naga gives the struct `name` of `module`.
fn struct_size(module: &naga::Module, name: &str) -> Option<usize> {
    module.types.iter().find_map(|(_, ty)| match &ty.inner {
        naga::TypeInner::Struct { span, .. } if ty.name.as_deref() == Some(name) => {
            Some(*span as usize)
        }
        _ => None,
    })
}

#[test]
fn shaders_validate_and_share_the_rust_layouts() {
    let visibility = module("visibility");
    // The shared structs are declared once, in common.wgsl, for every pass.
    for pass in ["visibility", "shade", "edges", "xray", "pick"] {
        let own = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("src/passes")
                .join(pass)
                .join(format!("{pass}.wgsl")),
        )
        .expect("shader source");
        assert!(
            !own.contains("struct Frame"),
            "{pass}.wgsl redeclares Frame"
        );
    }
    let shade = module("shade");
    let edges = module("edges");
    let xray = module("xray");
    let pick = module("pick");
    for (m, name, size) in [
        (&visibility, "Frame", size_of::<Frame>()),
        (&visibility, "Draw", size_of::<Draw>()),
        (&shade, "Frame", size_of::<Frame>()),
        (&shade, "Material", size_of::<Material>()),
        (&shade, "Light", size_of::<LightGpu>()),
        (&edges, "Frame", size_of::<Frame>()),
        (&edges, "Draw", size_of::<Draw>()),
        (&edges, "Segment", size_of::<Segment>()),
        (&xray, "Frame", size_of::<Frame>()),
        (&xray, "Draw", size_of::<Draw>()),
        (&xray, "Material", size_of::<Material>()),
        (&pick, "Frame", size_of::<Frame>()),
        (&pick, "Segment", size_of::<Segment>()),
    ] {
        assert_eq!(struct_size(m, name), Some(size), "{name}");
    }
}

#[test]
fn the_shaders_flags_are_the_rust_flags() {
    // Draw flags and the section cap marker are written by Rust or read by tests from Rust.
    let visibility = module("visibility");
    for (name, value) in [
        ("DRAW_CLOSED", DRAW_CLOSED),
        ("DRAW_INSIDE_OUT", DRAW_INSIDE_OUT),
        ("SECTION_CAP", SECTION_CAP),
    ] {
        assert_eq!(constant_u32(&visibility, name), Some(value), "{name}");
    }
}
