//! Hostile assemblies built from the corpus cube (`tr8_ha1_tc.stp`), as
//! `../shared/tools/bad_inputs.py` builds them. Shared by the STEP mapping tests and the
//! meshing crate's scene tests (included there with `#[path]`).
#![allow(dead_code)]

use std::path::Path;

/// The cube file with the chain appended before its `ENDSEC`.
pub fn chain(levels: usize, uses: usize) -> Option<Vec<u8>> {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/corpus/step/tr8_ha1_tc.stp");
    let Ok(cube) = std::fs::read(&path) else {
        eprintln!(
            "skipping: {} not found (clone without the shared data)",
            path.display()
        );
        return None;
    };
    let cube = String::from_utf8_lossy(&cube).into_owned();
    let tail = "ENDSEC;\nEND-ISO-10303-21;";
    let mut lines = Vec::new();
    let mut n = 100_000u64;
    let mut e = |s: String, lines: &mut Vec<String>| {
        n += 1;
        lines.push(format!("#{n}={s};"));
        n
    };
    // The cube's product definition, shape representation and placement.
    let (mut pd0, mut sr0, mut ax0) = (250u64, 220u64, 9u64);
    for k in 0..levels {
        let p = e(format!("PRODUCT('a{k}','a{k}','',(#245))"), &mut lines);
        let f = e(
            format!("PRODUCT_DEFINITION_FORMATION('1','',#{p})"),
            &mut lines,
        );
        let pd = e(format!("PRODUCT_DEFINITION('','',#{f},#246)"), &mut lines);
        let o = e("AXIS2_PLACEMENT_3D('',#204,#206,#205)".into(), &mut lines);
        let mut placements = Vec::new();
        for j in 0..uses {
            let c = e(
                format!("CARTESIAN_POINT('',({}.,0.,0.))", 10 * (j + 1)),
                &mut lines,
            );
            placements.push(e(
                format!("AXIS2_PLACEMENT_3D('',#{c},#206,#205)"),
                &mut lines,
            ));
        }
        let items: Vec<String> = std::iter::once(o)
            .chain(placements.iter().copied())
            .map(|i| format!("#{i}"))
            .collect();
        let sr = e(
            format!("SHAPE_REPRESENTATION('',({}),#219)", items.join(",")),
            &mut lines,
        );
        let ds = e(format!("PRODUCT_DEFINITION_SHAPE('','',#{pd})"), &mut lines);
        e(
            format!("SHAPE_DEFINITION_REPRESENTATION(#{ds},#{sr})"),
            &mut lines,
        );
        for a in placements {
            let t = e(
                format!("ITEM_DEFINED_TRANSFORMATION('','',#{ax0},#{a})"),
                &mut lines,
            );
            let r = e(
                format!(
                    "(REPRESENTATION_RELATIONSHIP('','',#{sr0},#{sr})\
                     REPRESENTATION_RELATIONSHIP_WITH_TRANSFORMATION(#{t})\
                     SHAPE_REPRESENTATION_RELATIONSHIP())"
                ),
                &mut lines,
            );
            let u = e(
                format!("NEXT_ASSEMBLY_USAGE_OCCURRENCE('u','','u',#{pd},#{pd0},$)"),
                &mut lines,
            );
            let us = e(format!("PRODUCT_DEFINITION_SHAPE('','',#{u})"), &mut lines);
            e(
                format!("CONTEXT_DEPENDENT_SHAPE_REPRESENTATION(#{r},#{us})"),
                &mut lines,
            );
        }
        (pd0, sr0, ax0) = (pd, sr, o);
    }
    let text = cube.replace(tail, &format!("{}\n{tail}", lines.join("\n")));
    Some(text.into_bytes())
}
