//! Every pass's WGSL parses and validates with naga (the compiler wgpu uses), and the structs
//! shared with Rust have the members (names and offsets, in order) and sizes of their
//! `cadre_render::layout` twins.

use cadre_render::SECTION_CAP;
use cadre_render::layout::{
    BackdropUniform, Call, DRAW_ATTRIBUTES, DRAW_CLOSED, DRAW_FIRST_LOCATION, DRAW_INSIDE_OUT,
    Draw, EDGES_ALL, EDGES_HIDDEN_DASHED, EDGES_VISIBLE, FILL_BACKGROUND, FILL_NONE, FILL_SHADED,
    FrameUniform, GpuStruct, LightGpu, LightRig, LineFrame, LinePoint, LineStyleGpu, Local,
    Material, Member, PROJECTION_ORTHOGRAPHIC, PROJECTION_PERSPECTIVE, PickRegion, Primitive,
    Segment, TextFrame, TextGlyph, TextLabel, TrimCall, TrimSurface, TrimTask,
};
use cadre_render::layout::{Binding, INSTANCE_BINDINGS, PassShader, pass_shaders};

/// The renderer's shader named `name`, as it compiles it.
fn shader(name: &str) -> PassShader {
    pass_shaders()
        .into_iter()
        .find(|s| s.name == name)
        .unwrap_or_else(|| panic!("no shader {name}"))
}

/// Parses and validates one of the renderer's shaders; returns the module.
fn module(name: &str) -> naga::Module {
    validated(name, &shader(name).source)
}

fn validated(name: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(source)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::empty(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{name}: {e:?}"));
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

/// Members (name, offset) and size naga gives the struct `name` of `module`.
fn naga_struct(module: &naga::Module, name: &str) -> Option<(Vec<Member>, usize)> {
    module.types.iter().find_map(|(_, ty)| match &ty.inner {
        naga::TypeInner::Struct { members, span } if ty.name.as_deref() == Some(name) => {
            let members = members
                .iter()
                .map(|m| Member {
                    name: m.name.clone().map_or("?", |n| n.leak()),
                    offset: m.offset as usize,
                })
                .collect();
            Some((members, *span as usize))
        }
        _ => None,
    })
}

/// Compares a Rust layout with its WGSL twin: the same members, in order, at the same
/// offsets, and the same size. The error names the first member that differs.
fn compare(
    name: &str,
    rust: &[Member],
    rust_size: usize,
    wgsl: &[Member],
    wgsl_size: usize,
) -> Result<(), String> {
    for (i, (r, w)) in rust.iter().zip(wgsl).enumerate() {
        if r != w {
            return Err(format!(
                "{name} member {i}: Rust {} at {}, WGSL {} at {}",
                r.name, r.offset, w.name, w.offset
            ));
        }
    }
    if rust.len() != wgsl.len() {
        return Err(format!(
            "{name}: {} members in Rust, {} in WGSL",
            rust.len(),
            wgsl.len()
        ));
    }
    if rust_size != wgsl_size {
        return Err(format!(
            "{name}: {rust_size} bytes in Rust, {wgsl_size} in WGSL"
        ));
    }
    Ok(())
}

/// Checks one layout against its twin in `module`, if the module declares it.
fn check<T: GpuStruct>(pass: &str, module: &naga::Module) -> Result<bool, String> {
    let Some((wgsl, wgsl_size)) = naga_struct(module, T::WGSL_NAME) else {
        return Ok(false);
    };
    compare(
        &format!("{pass}: {}", T::WGSL_NAME),
        &T::members(),
        size_of::<T>(),
        &wgsl,
        wgsl_size,
    )
    .map(|()| true)
}

#[test]
fn shaders_validate_and_share_the_rust_layouts() {
    // The shared structs are declared once, in common.wgsl, for every pass.
    for pass in pass_shaders() {
        for name in [
            "FrameUniform",
            "Draw",
            "Material",
            "Segment",
            "Light",
            "LightRig",
            "Local",
            "Call",
            "PickRegion",
            "Primitive",
            "InstanceIds",
            "VisibilityOut",
        ] {
            assert!(
                pass.source.matches(&format!("struct {name} ")).count() <= 1,
                "{} declares {name} twice",
                pass.name
            );
        }
    }
    let mut found = std::collections::BTreeMap::<&str, usize>::new();
    for pass in pass_shaders() {
        let m = validated(pass.name, &pass.source);
        let pass = pass.name;
        for (name, hit) in [
            ("FrameUniform", check::<FrameUniform>(pass, &m)),
            ("Draw", check::<Draw>(pass, &m)),
            ("Material", check::<Material>(pass, &m)),
            ("Segment", check::<Segment>(pass, &m)),
            ("Light", check::<LightGpu>(pass, &m)),
            ("LightRig", check::<LightRig>(pass, &m)),
            ("Local", check::<Local>(pass, &m)),
            ("Call", check::<Call>(pass, &m)),
            ("PickRegion", check::<PickRegion>(pass, &m)),
            ("Primitive", check::<Primitive>(pass, &m)),
            ("TrimSurface", check::<TrimSurface>(pass, &m)),
            ("TrimTask", check::<TrimTask>(pass, &m)),
            ("TrimCall", check::<TrimCall>(pass, &m)),
            ("LinePoint", check::<LinePoint>(pass, &m)),
            ("LineStyle", check::<LineStyleGpu>(pass, &m)),
            ("LineFrame", check::<LineFrame>(pass, &m)),
            ("BackdropUniform", check::<BackdropUniform>(pass, &m)),
            ("TextGlyph", check::<TextGlyph>(pass, &m)),
            ("TextLabel", check::<TextLabel>(pass, &m)),
            ("TextFrame", check::<TextFrame>(pass, &m)),
        ] {
            if hit.unwrap_or_else(|e| panic!("{e}")) {
                *found.entry(name).or_default() += 1;
            }
        }
    }
    // Every layout was really compared somewhere (naga drops nothing we rely on).
    assert_eq!(found.len(), 20, "{found:?}");
}

#[test]
fn swapped_fields_are_caught() {
    // Negative control: the Rust FrameUniform with two fields of the same type swapped (what the
    // old size-only comparison let through) and with one field dropped.
    let m = module("shade");
    let (wgsl, size) = naga_struct(&m, "FrameUniform").expect("FrameUniform in shade");
    let mut swapped = FrameUniform::members();
    let (a, b) = (
        swapped
            .iter()
            .position(|f| f.name == "edge_colour")
            .unwrap(),
        swapped
            .iter()
            .position(|f| f.name == "hidden_colour")
            .unwrap(),
    );
    let (oa, ob) = (swapped[a].offset, swapped[b].offset);
    swapped[a].offset = ob;
    swapped[b].offset = oa;
    swapped.sort_by_key(|f| f.offset);
    let err = compare(
        "FrameUniform",
        &swapped,
        size_of::<FrameUniform>(),
        &wgsl,
        size,
    )
    .unwrap_err();
    assert!(err.contains("hidden_colour"), "{err}");
    let mut short = FrameUniform::members();
    short.pop();
    assert!(
        compare(
            "FrameUniform",
            &short,
            size_of::<FrameUniform>(),
            &wgsl,
            size
        )
        .is_err()
    );
    assert!(
        compare(
            "FrameUniform",
            &FrameUniform::members(),
            size_of::<FrameUniform>() + 16,
            &wgsl,
            size
        )
        .is_err()
    );
    // And the true layout passes.
    compare(
        "FrameUniform",
        &FrameUniform::members(),
        size_of::<FrameUniform>(),
        &wgsl,
        size,
    )
    .unwrap();
}

/// The bindings of bind group `group` that `module` declares, in binding order, as
/// [`Binding`]s; a declaration in a group past 1 is an error.
fn naga_bindings(module: &naga::Module, group: u32) -> Result<Vec<(u32, Binding)>, String> {
    let type_name = |h: naga::Handle<naga::Type>| -> Result<&'static str, String> {
        let ty = &module.types[h];
        if let Some(name) = &ty.name {
            return Ok(name.clone().leak());
        }
        match ty.inner {
            naga::TypeInner::Vector {
                size: naga::VectorSize::Quad,
                scalar: naga::Scalar::U32,
            } => Ok("vec4<u32>"),
            naga::TypeInner::Vector {
                size: naga::VectorSize::Quad,
                scalar: naga::Scalar::F32,
            } => Ok("vec4<f32>"),
            naga::TypeInner::Vector {
                size: naga::VectorSize::Bi,
                scalar: naga::Scalar::U32,
            } => Ok("vec2<u32>"),
            naga::TypeInner::Scalar(naga::Scalar::U32) => Ok("u32"),
            naga::TypeInner::Scalar(naga::Scalar::F32) => Ok("f32"),
            ref other => Err(format!("unnamed binding type {other:?}")),
        }
    };
    let mut out = Vec::new();
    for (_, var) in module.global_variables.iter() {
        let Some(rb) = &var.binding else { continue };
        if rb.group > 1 {
            return Err(format!("{:?} is in group {}", var.name, rb.group));
        }
        if rb.group != group {
            continue;
        }
        let binding = match (var.space, &module.types[var.ty].inner) {
            (naga::AddressSpace::Uniform, _) => Binding::Uniform(type_name(var.ty)?),
            (naga::AddressSpace::Storage { access }, naga::TypeInner::Array { base, .. })
                if !access.contains(naga::StorageAccess::STORE) =>
            {
                Binding::Storage(type_name(*base)?)
            }
            (naga::AddressSpace::Storage { access }, naga::TypeInner::Array { base, .. })
                if matches!(
                    module.types[*base].inner,
                    naga::TypeInner::Atomic(naga::Scalar::U32)
                ) && access.contains(naga::StorageAccess::STORE) =>
            {
                Binding::AtomicStorage
            }
            (naga::AddressSpace::Storage { access }, naga::TypeInner::Array { base, .. })
                if access.contains(naga::StorageAccess::STORE) =>
            {
                Binding::StorageWrite(type_name(*base)?)
            }
            (
                naga::AddressSpace::Handle,
                naga::TypeInner::Image {
                    dim: naga::ImageDimension::D2,
                    arrayed: false,
                    class: naga::ImageClass::Sampled { kind, multi: false },
                },
            ) => match kind {
                naga::ScalarKind::Float => Binding::FloatTexture,
                naga::ScalarKind::Uint => Binding::UintTexture,
                other => return Err(format!("texture of {other:?}")),
            },
            (naga::AddressSpace::Handle, naga::TypeInner::Sampler { comparison: false }) => {
                Binding::Sampler
            }
            (space, inner) => return Err(format!("{:?}: {space:?} {inner:?}", var.name)),
        };
        out.push((rb.binding, binding));
    }
    out.sort_by_key(|b| b.0);
    Ok(out)
}

/// Compares a pass's Rust binding list (binding = index) with its WGSL declarations.
fn compare_bindings(pass: &str, rust: &[Binding], wgsl: &[(u32, Binding)]) -> Result<(), String> {
    // WGSL does not say whether a float texture is filtered: the sampler bound with it does.
    let rust: Vec<(u32, Binding)> = rust
        .iter()
        .enumerate()
        .map(|(i, b)| match b {
            Binding::FilteredTexture => (i as u32, Binding::FloatTexture),
            b => (i as u32, *b),
        })
        .collect();
    if rust != wgsl {
        return Err(format!(
            "{pass}: Rust binds {rust:?}, the WGSL declares {wgsl:?}"
        ));
    }
    Ok(())
}

#[test]
fn every_pass_binds_what_its_shader_declares() {
    for pass in pass_shaders() {
        let m = validated(pass.name, &pass.source);
        let wgsl = naga_bindings(&m, 0).unwrap_or_else(|e| panic!("{}: {e}", pass.name));
        compare_bindings(pass.name, pass.bindings, &wgsl).unwrap_or_else(|e| panic!("{e}"));
        // Group 1: the instances, for the passes that draw them, and nothing for the others.
        let wgsl = naga_bindings(&m, 1).unwrap_or_else(|e| panic!("{}: {e}", pass.name));
        let instances = if pass.instanced {
            INSTANCE_BINDINGS
        } else {
            &[]
        };
        compare_bindings(pass.name, instances, &wgsl).unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn a_wrong_instance_binding_list_is_caught() {
    // Negative control: the records and locals swapped (both storage arrays), or the
    // instance group missing from a pass that declares it.
    let wgsl = naga_bindings(&module("visibility/mesh"), 1).unwrap();
    compare_bindings("visibility/mesh", INSTANCE_BINDINGS, &wgsl).unwrap();
    let mut swapped = INSTANCE_BINDINGS.to_vec();
    swapped.swap(1, 2);
    assert!(compare_bindings("visibility/mesh", &swapped, &wgsl).is_err());
    assert!(compare_bindings("visibility/mesh", &[], &wgsl).is_err());
}

#[test]
fn a_wrong_binding_list_is_caught() {
    // Negative control: shade's list with its materials and lights swapped (both storage
    // arrays, which wgpu's own validation accepts), and with its last binding dropped.
    let shade = shader("shade").bindings;
    let wgsl = naga_bindings(&module("shade"), 0).unwrap();
    compare_bindings("shade", shade, &wgsl).unwrap();
    let mut swapped = shade.to_vec();
    swapped.swap(1, 4);
    assert!(compare_bindings("shade", &swapped, &wgsl).is_err());
    assert!(compare_bindings("shade", &shade[..shade.len() - 1], &wgsl).is_err());
}

#[test]
fn the_shaders_flags_are_the_rust_flags() {
    // Draw flags and the section cap marker are written by Rust or read by tests from Rust.
    let visibility = module("visibility/mesh");
    for (name, value) in [
        ("DRAW_CLOSED", DRAW_CLOSED),
        ("DRAW_INSIDE_OUT", DRAW_INSIDE_OUT),
        ("SECTION_CAP", SECTION_CAP),
        ("PROJECTION_PERSPECTIVE", PROJECTION_PERSPECTIVE),
        ("PROJECTION_ORTHOGRAPHIC", PROJECTION_ORTHOGRAPHIC),
        ("FILL_SHADED", FILL_SHADED),
        ("FILL_BACKGROUND", FILL_BACKGROUND),
        ("FILL_NONE", FILL_NONE),
        ("EDGES_VISIBLE", EDGES_VISIBLE),
        ("EDGES_ALL", EDGES_ALL),
        ("EDGES_HIDDEN_DASHED", EDGES_HIDDEN_DASHED),
        ("MAX_SECTIONS", cadre_render::MAX_SECTIONS as u32),
        ("LINE_JOIN_MITER", cadre_render::layout::LINE_JOIN_MITER),
        ("LINE_JOIN_ROUND", cadre_render::layout::LINE_JOIN_ROUND),
        ("LINE_JOIN_BEVEL", cadre_render::layout::LINE_JOIN_BEVEL),
        ("LINE_CAP_BUTT", cadre_render::layout::LINE_CAP_BUTT),
        ("LINE_CAP_SQUARE", cadre_render::layout::LINE_CAP_SQUARE),
        ("LINE_CAP_ROUND", cadre_render::layout::LINE_CAP_ROUND),
        ("LINE_WORLD_WIDTH", cadre_render::layout::LINE_WORLD_WIDTH),
        (
            "LINE_POINT_COLOURS",
            cadre_render::layout::LINE_POINT_COLOURS,
        ),
        ("LINE_HIDDEN_SHOWN", cadre_render::layout::LINE_HIDDEN_SHOWN),
        (
            "LINE_HIDDEN_STYLED",
            cadre_render::layout::LINE_HIDDEN_STYLED,
        ),
        ("LINE_WHOLE", cadre_render::layout::LINE_WHOLE),
        ("TEXT_QUAD_GLYPH", cadre_render::layout::TEXT_QUAD_GLYPH),
        ("TEXT_QUAD_BOX", cadre_render::layout::TEXT_QUAD_BOX),
        ("TEXT_QUAD_LEADER", cadre_render::layout::TEXT_QUAD_LEADER),
        ("TEXT_QUAD_FILL", cadre_render::layout::TEXT_QUAD_FILL),
        (
            "TEXT_ANCHOR_SCREEN",
            cadre_render::layout::TEXT_ANCHOR_SCREEN,
        ),
        (
            "TEXT_ANCHOR_BILLBOARD",
            cadre_render::layout::TEXT_ANCHOR_BILLBOARD,
        ),
        ("TEXT_ANCHOR_PLANE", cadre_render::layout::TEXT_ANCHOR_PLANE),
    ] {
        assert_eq!(constant_u32(&visibility, name), Some(value), "{name}");
    }
    let analytic = module("visibility/analytic");
    for (name, value) in [
        ("PRIMITIVE_SPHERE", cadre_render::analytic::PRIMITIVE_SPHERE),
        (
            "PRIMITIVE_RECTANGLE",
            cadre_render::analytic::PRIMITIVE_RECTANGLE,
        ),
        (
            "PRIMITIVE_QUADRIC_PATCH",
            cadre_render::analytic::PRIMITIVE_QUADRIC_PATCH,
        ),
        (
            "PRIMITIVE_QUADRIC_VOLUME",
            cadre_render::analytic::PRIMITIVE_QUADRIC_VOLUME,
        ),
        ("DRAW_CLOSED", DRAW_CLOSED),
    ] {
        assert_eq!(constant_u32(&analytic, name), Some(value), "{name}");
    }
    // Negative control: a constant the shaders do not declare is not found.
    assert_eq!(constant_u32(&visibility, "FILL_SOMETHING"), None);
}

/// The shader location and vertex format of each member of the WGSL struct `name` whose
/// members are all vertex inputs, in declaration order.
fn naga_vertex_inputs(
    module: &naga::Module,
    name: &str,
) -> Result<Vec<(u32, wgpu::VertexFormat)>, String> {
    let members = module
        .types
        .iter()
        .find_map(|(_, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, .. } if ty.name.as_deref() == Some(name) => {
                Some(members)
            }
            _ => None,
        })
        .ok_or_else(|| format!("no struct {name}"))?;
    members
        .iter()
        .map(|m| {
            let Some(naga::Binding::Location { location, .. }) = m.binding else {
                return Err(format!("{name}.{:?} has no location", m.name));
            };
            let format = match module.types[m.ty].inner {
                naga::TypeInner::Vector {
                    size: naga::VectorSize::Quad,
                    scalar,
                } if scalar == naga::Scalar::F32 => wgpu::VertexFormat::Float32x4,
                naga::TypeInner::Vector {
                    size: naga::VectorSize::Quad,
                    scalar,
                } if scalar == naga::Scalar::U32 => wgpu::VertexFormat::Uint32x4,
                ref other => return Err(format!("{name}.{:?}: {other:?}", m.name)),
            };
            Ok((location, format))
        })
        .collect()
}

/// Compares the Rust attributes a [`Draw`] is read through with `DrawAttributes` of `module`:
/// the same locations and formats, in order, and offsets that land on the WGSL `Draw`'s
/// members (the model's columns, the normal matrix's, then material, instance, flags).
fn compare_draw_attributes(
    module: &naga::Module,
    rust: &[wgpu::VertexAttribute],
) -> Result<(), String> {
    let wgsl = naga_vertex_inputs(module, "DrawAttributes")?;
    if wgsl.len() != rust.len() {
        return Err(format!(
            "{} WGSL attributes, {} Rust",
            wgsl.len(),
            rust.len()
        ));
    }
    let (draw, _) = naga_struct(module, "Draw").ok_or("no struct Draw")?;
    let offset = |name: &str| {
        draw.iter()
            .find(|m| m.name == name)
            .map(|m| m.offset as u64)
            .ok_or(format!("Draw has no {name}"))
    };
    let (model, normal, material) = (offset("model")?, offset("normal")?, offset("material")?);
    if offset("instance")? != material + 4 || offset("flags")? != material + 8 {
        return Err("material, instance, flags are not one vec4<u32>".into());
    }
    let expected_offsets = [0, 16, 32, 48].map(|c| model + c).into_iter();
    let expected_offsets = expected_offsets
        .chain([0, 16, 32].map(|c| normal + c))
        .chain([material]);
    for (i, ((r, (location, format)), offset)) in
        rust.iter().zip(&wgsl).zip(expected_offsets).enumerate()
    {
        if (r.shader_location, r.format) != (*location, *format) {
            return Err(format!(
                "attribute {i}: Rust {:?} at location {}, WGSL {format:?} at {location}",
                r.format, r.shader_location
            ));
        }
        if r.offset != offset {
            return Err(format!(
                "attribute {i}: Rust offset {}, WGSL Draw member at {offset}",
                r.offset
            ));
        }
    }
    Ok(())
}

#[test]
fn draw_records_read_as_attributes_match_their_wgsl_twin() {
    // The passes whose direct calls read their records as attributes.
    for pass in ["visibility/mesh", "edges"] {
        compare_draw_attributes(&module(pass), &DRAW_ATTRIBUTES)
            .unwrap_or_else(|e| panic!("{pass}: {e}"));
    }
    assert_eq!(DRAW_ATTRIBUTES[0].shader_location, DRAW_FIRST_LOCATION);
}

#[test]
fn wrong_draw_attributes_are_caught() {
    // Negative controls: two columns of the model swapped (same format, same locations set),
    // and the ids read as floats.
    let module = module("visibility/mesh");
    let mut swapped = DRAW_ATTRIBUTES;
    swapped.swap(1, 2);
    (swapped[1].shader_location, swapped[2].shader_location) = (9, 10);
    let err = compare_draw_attributes(&module, &swapped).expect_err("swapped columns");
    assert!(err.contains("offset"), "{err}");
    let mut floats = DRAW_ATTRIBUTES;
    floats[7].format = wgpu::VertexFormat::Float32x4;
    let err = compare_draw_attributes(&module, &floats).expect_err("ids as floats");
    assert!(err.contains("attribute 7"), "{err}");
}

/// What the leaves of an expression tree read, for [`uniform_only_control_flow`].
#[derive(Default)]
struct Leaves {
    /// A value loaded from a uniform buffer.
    uniform: bool,
    /// Anything else that varies: storage, textures, arguments, calls, queries.
    other: bool,
}

/// Walks the expression `e` of `function` down to its leaves.
fn leaves(
    module: &naga::Module,
    function: &naga::Function,
    e: naga::Handle<naga::Expression>,
    out: &mut Leaves,
) {
    use naga::Expression as E;
    let mut walk = |h| leaves(module, function, h, out);
    match &function.expressions[e] {
        E::Literal(_) | E::Constant(_) | E::Override(_) | E::ZeroValue(_) | E::LocalVariable(_) => {
        }
        E::GlobalVariable(g) => {
            if module.global_variables[*g].space == naga::AddressSpace::Uniform {
                out.uniform = true;
            } else {
                out.other = true;
            }
        }
        E::Load { pointer } => walk(*pointer),
        E::AccessIndex { base, .. } => walk(*base),
        E::Access { base, index } => {
            walk(*base);
            walk(*index);
        }
        E::Splat { value, .. } => walk(*value),
        E::Swizzle { vector, .. } => walk(*vector),
        E::Compose { components, .. } => components.iter().for_each(|c| walk(*c)),
        E::Unary { expr, .. } => walk(*expr),
        E::Binary { left, right, .. } => {
            walk(*left);
            walk(*right);
        }
        E::Select {
            condition,
            accept,
            reject,
        } => {
            walk(*condition);
            walk(*accept);
            walk(*reject);
        }
        E::Relational { argument, .. } => walk(*argument),
        E::As { expr, .. } => walk(*expr),
        E::Math {
            arg,
            arg1,
            arg2,
            arg3,
            ..
        } => {
            walk(*arg);
            [arg1, arg2, arg3]
                .into_iter()
                .flatten()
                .for_each(|a| walk(*a));
        }
        _ => out.other = true,
    }
}

/// The loops and `if`s of `module` whose condition reads a uniform buffer and nothing else
/// that varies (besides local variables: a loop's counter), by function name (`if`s marked).
/// lavapipe inlines such uniform values into the shader and compiles it again each time the
/// uniforms are bound (measured: a recompile per edge draw call, 8–20 ms of a frame).
fn uniform_only_control_flow(module: &naga::Module) -> Vec<String> {
    fn visit(
        module: &naga::Module,
        function: &naga::Function,
        block: &naga::Block,
        name: &str,
        found: &mut Vec<String>,
    ) {
        for statement in block.iter() {
            match statement {
                naga::Statement::Loop {
                    body,
                    continuing,
                    break_if,
                } => {
                    let mut conditions: Vec<_> = break_if.iter().copied().collect();
                    // WGSL's `for` and `while` open their body with `if cond {} else { break; }`.
                    if let Some(naga::Statement::If {
                        condition,
                        accept,
                        reject,
                    }) = body.iter().find(|s| !matches!(s, naga::Statement::Emit(_)))
                    {
                        let breaks = |b: &naga::Block| {
                            matches!(b.iter().next(), Some(naga::Statement::Break))
                        };
                        if breaks(accept) || breaks(reject) {
                            conditions.push(*condition);
                        }
                    }
                    for c in conditions {
                        let mut l = Leaves::default();
                        leaves(module, function, c, &mut l);
                        if l.uniform && !l.other {
                            found.push(name.to_string());
                        }
                    }
                    visit(module, function, body, name, found);
                    visit(module, function, continuing, name, found);
                }
                naga::Statement::Block(b) => visit(module, function, b, name, found),
                naga::Statement::If {
                    condition,
                    accept,
                    reject,
                } => {
                    // A loop's exit test is the loop's (above).
                    let breaks =
                        |b: &naga::Block| matches!(b.iter().next(), Some(naga::Statement::Break));
                    let mut l = Leaves::default();
                    leaves(module, function, *condition, &mut l);
                    if l.uniform && !l.other && !breaks(accept) && !breaks(reject) {
                        found.push(format!("{name} (if)"));
                    }
                    visit(module, function, accept, name, found);
                    visit(module, function, reject, name, found);
                }
                naga::Statement::Switch { cases, .. } => {
                    cases
                        .iter()
                        .for_each(|c| visit(module, function, &c.body, name, found));
                }
                _ => {}
            }
        }
    }
    let mut found = Vec::new();
    for (_, f) in module.functions.iter() {
        visit(
            module,
            f,
            &f.body,
            f.name.as_deref().unwrap_or("?"),
            &mut found,
        );
    }
    for ep in &module.entry_points {
        visit(
            module,
            &ep.function,
            &ep.function.body,
            &ep.name,
            &mut found,
        );
    }
    found
}

#[test]
fn no_control_flow_is_decided_by_uniforms_alone() {
    for pass in pass_shaders() {
        let m = validated(pass.name, &pass.source);
        let found = uniform_only_control_flow(&m);
        assert!(
            found.is_empty(),
            "{}: control flow decided by uniforms alone in {found:?}",
            pass.name
        );
    }
}

#[test]
fn control_flow_decided_by_a_uniform_is_caught() {
    // Negative controls: the section loop as it was, and the forms that pass.
    let source = |bound: &str| {
        format!(
            "struct F {{ n: u32 }}
             @group(0) @binding(0) var<uniform> f: F;
             @group(0) @binding(1) var<storage, read> s: array<u32>;
             @fragment fn main() -> @location(0) vec4<f32> {{
                 var x = 0u;
                 for (var i = 0u; i < {bound}; i++) {{ x += s[i]; }}
                 return vec4<f32>(f32(x));
             }}"
        )
    };
    let flagged = validated("control", &source("f.n"));
    assert_eq!(uniform_only_control_flow(&flagged), ["main"]);
    let flagged = validated("control", &source("f.n * 2u + 1u"));
    assert_eq!(uniform_only_control_flow(&flagged), ["main"]);
    let fine = validated("control", &source("min(f.n, arrayLength(&s))"));
    assert!(uniform_only_control_flow(&fine).is_empty());
    let fine = validated("control", &source("3u"));
    assert!(uniform_only_control_flow(&fine).is_empty());
    // An `if` on a uniform alone, and one joined with a varying value.
    let branch = |condition: &str| {
        format!(
            "struct F {{ n: u32 }}
             @group(0) @binding(0) var<uniform> f: F;
             @fragment fn main(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {{
                 var x = 0.0;
                 if {condition} {{ x = 1.0; }}
                 return vec4<f32>(x);
             }}"
        )
    };
    let flagged = validated("control", &branch("f.n == 1u"));
    assert_eq!(uniform_only_control_flow(&flagged), ["main (if)"]);
    let fine = validated("control", &branch("(f.n == 1u) & (p.x > 2.0)"));
    assert!(uniform_only_control_flow(&fine).is_empty());
}
