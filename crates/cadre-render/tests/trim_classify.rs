//! The GPU's trim test (`cadre_trim::TRIM_WGSL`) answers as its CPU oracle
//! (`TrimBuffers::classify`) on the same packed words: random face-local points of every face
//! of the bundled assembly and of a sliver face (two curves a hair apart, whose tree holds
//! fallback leaves), classified in a compute shader on the adapter the tests draw on.
//! Negative control: the same points asked of the next face's tree disagree often.

mod common;

use cadre_trim::{QuadPiece, TrimBuffers, TrimTree, Uv, model_trees};

/// The shader: the five trim buffers, the queries (face, q as f32 bits), the answers.
fn shader() -> String {
    format!(
        "@group(0) @binding(0) var<storage, read> trim_faces: array<TrimFace>;
         @group(0) @binding(1) var<storage, read> trim_nodes: array<u32>;
         @group(0) @binding(2) var<storage, read> trim_floats: array<f32>;
         @group(0) @binding(3) var<storage, read> trim_piece_offsets: array<u32>;
         @group(0) @binding(4) var<storage, read> trim_lists: array<u32>;
         @group(0) @binding(5) var<storage, read> queries: array<vec4<u32>>;
         @group(0) @binding(6) var<storage, read_write> answers: array<u32>;
         {}
         @compute @workgroup_size(64)
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
             if id.x >= arrayLength(&queries) {{ return; }}
             let query = queries[id.x];
             let q = vec2<f32>(bitcast<f32>(query.y), bitcast<f32>(query.z));
             // w: 0 for a point, else the side of the cell from q (its answer 10 + class).
             let side = bitcast<f32>(query.w);
             if query.w == 0u {{
                 answers[id.x] = select(0u, 1u, trim_classify(query.x, q));
             }} else {{
                 answers[id.x] = 10u + trim_cell(query.x, q, q + vec2<f32>(side));
             }}
         }}",
        cadre_trim::TRIM_WGSL
    )
}

/// The GPU's answers for `queries` (face, face-local point): on the face or not.
fn gpu_answers(
    gpu: &cadre_render::Gpu,
    buffers: &TrimBuffers,
    queries: &[(u32, [f32; 2])],
) -> Vec<u32> {
    let cells: Vec<(u32, [f32; 2], f32)> = queries.iter().map(|&(f, q)| (f, q, 0.0)).collect();
    gpu_cell_answers(gpu, buffers, &cells)
}

/// The GPU's answers for `queries` (face, face-local corner, side): a point's (side 0) on
/// the face or not, a cell's `10 + trim_cell`.
fn gpu_cell_answers(
    gpu: &cadre_render::Gpu,
    buffers: &TrimBuffers,
    queries: &[(u32, [f32; 2], f32)],
) -> Vec<u32> {
    let words: Vec<u32> = queries
        .iter()
        .flat_map(|(f, q, side)| [*f, q[0].to_bits(), q[1].to_bits(), side.to_bits()])
        .collect();
    let faces = buffers.face_words();
    let inputs: [&[u8]; 6] = [
        bytemuck::cast_slice(&faces),
        bytemuck::cast_slice(&buffers.nodes),
        bytemuck::cast_slice(&buffers.floats),
        bytemuck::cast_slice(&buffers.piece_offsets),
        bytemuck::cast_slice(&buffers.lists),
        bytemuck::cast_slice(&words),
    ];
    let count = queries.len() as u32;
    let bytes = common::run_compute(gpu, &shader(), &inputs, (count, 4 * u64::from(count)));
    bytemuck::cast_slice(&bytes).to_vec()
}

/// A sliver face: a curve out and the same curve back a hair below it.
fn sliver() -> TrimTree {
    let curve = |k: usize, offset: f64| {
        let t = k as f64 / 8.0;
        Uv::new(2.0 * t, 0.4 * (2.0 * t - 1.0).powi(2) + offset)
    };
    let mut pieces = Vec::new();
    for k in 0..8 {
        pieces.push(QuadPiece::line(curve(k, 1e-6), curve(k + 1, 1e-6)));
    }
    pieces.push(QuadPiece::line(curve(8, 1e-6), curve(8, 0.0)));
    for k in (0..8).rev() {
        pieces.push(QuadPiece::line(curve(k + 1, 0.0), curve(k, 0.0)));
    }
    pieces.push(QuadPiece::line(curve(0, 0.0), curve(0, 1e-6)));
    TrimTree::build(&pieces)
}

#[test]
fn the_gpu_trim_test_answers_as_the_cpu_oracle() {
    let gpu = common::gpu();
    let (model, _) = common::model_and_scene("pin-assembly.step");
    let trees = model_trees(&model, 0.01);
    let mut buffers = trees.buffers.clone();
    let sliver_face = buffers.push(&sliver()).expect("packs") as u32;
    assert!(
        sliver().fallback_leaves() > 0,
        "the sliver has no fallback leaf"
    );
    // Both kinds of root are asked: a whole-face parity root and a tree.
    let roots: Vec<u32> = buffers
        .faces
        .iter()
        .map(|f| buffers.nodes[f.nodes as usize] >> 29)
        .collect();
    assert!(
        roots.contains(&cadre_trim::layout::KIND_ALL),
        "no whole-face root"
    );
    assert!(roots.contains(&cadre_trim::layout::KIND_SPLIT), "no tree");
    // Both point layouts are asked: pieces on their face's grid (the assembly's) and in
    // `f32` (the sliver's).
    let on_grid = buffers
        .piece_offsets
        .iter()
        .filter(|w| *w & cadre_trim::layout::PIECE_ON_GRID != 0)
        .count();
    assert!(
        on_grid > 0 && on_grid < buffers.piece_offsets.len(),
        "{on_grid} of {} pieces on a grid",
        buffers.piece_offsets.len()
    );
    let mut random = common::xorshift(0x2545_f491_4f6c_dd1d);
    let mut queries = Vec::new();
    for (face, record) in buffers.faces.iter().enumerate() {
        for _ in 0..2000 {
            // Past the box a little too.
            let q = [
                (random() * 1.1 - 0.05) * record.size[0],
                (random() * 1.1 - 0.05) * record.size[1],
            ];
            queries.push((face as u32, q));
        }
    }
    let cpu: Vec<u32> = queries
        .iter()
        .map(|(f, q)| {
            let origin = buffers.faces[*f as usize].origin;
            let p = origin + Uv::new(f64::from(q[0]), f64::from(q[1]));
            u32::from(buffers.classify(*f as usize, p))
        })
        .collect();
    let on = cpu.iter().filter(|&&a| a == 1).count();
    assert!(
        on > queries.len() / 10 && on < queries.len() * 9 / 10,
        "{on} of {} on",
        queries.len()
    );
    let gpu_out = gpu_answers(&gpu, &buffers, &queries);
    let differ = cpu.iter().zip(&gpu_out).filter(|(a, b)| a != b).count();
    // f32 arithmetic may be contracted differently there: a point on a boundary may go either
    // way.
    assert!(
        differ * 10_000 <= queries.len(),
        "{}: the GPU differs from the CPU oracle on {differ} of {} points",
        gpu.info.name,
        queries.len()
    );
    let sliver_queries = queries.iter().filter(|(f, _)| *f == sliver_face).count();
    assert!(sliver_queries > 0);
    // Negative control: the next face's tree for each point.
    let faces = buffers.faces.len() as u32;
    let shifted: Vec<(u32, [f32; 2])> =
        queries.iter().map(|(f, q)| ((f + 1) % faces, *q)).collect();
    let wrong = gpu_answers(&gpu, &buffers, &shifted);
    let differ = cpu.iter().zip(&wrong).filter(|(a, b)| a != b).count();
    assert!(
        differ * 20 > queries.len(),
        "the next face's tree differs on {differ} only"
    );
}

/// The GPU's cell test (`trim_cell`, which the trim back-end's vertex shader asks of every
/// grid cell) answers as its CPU twin (`TrimBuffers::classify_cell`) on random cells of every
/// face of the bundled assembly and of the sliver. Negative control: the same cells asked of
/// the next face's tree.
#[test]
fn the_gpu_cell_test_answers_as_the_cpu_oracle() {
    use cadre_trim::CellClass;
    let gpu = common::gpu();
    let (model, _) = common::model_and_scene("pin-assembly.step");
    let mut buffers = model_trees(&model, 0.01).buffers;
    buffers.push(&sliver()).expect("packs");
    let mut random = common::xorshift(0x9e37_79b9_7f4a_7c15);
    let mut queries = Vec::new();
    for (face, record) in buffers.faces.iter().enumerate() {
        for k in 0..2000 {
            let side = record.size[0].min(record.size[1]) / (2 << (k % 6)) as f32;
            let q = [
                (random() * 1.1 - 0.05) * record.size[0],
                (random() * 1.1 - 0.05) * record.size[1],
            ];
            queries.push((face as u32, q, side));
        }
    }
    let class = |c: CellClass| match c {
        CellClass::Out => 10u32,
        CellClass::In => 11,
        CellClass::Crossed => 12,
    };
    let cpu_of = |face: usize, q: [f32; 2], side: f32| {
        class(buffers.classify_cell(face, q, [q[0] + side, q[1] + side]))
    };
    let cpu: Vec<u32> = queries
        .iter()
        .map(|&(f, q, side)| cpu_of(f as usize, q, side))
        .collect();
    let known = cpu.iter().filter(|&&c| c != 12).count();
    assert!(
        known > queries.len() / 4,
        "{known} of {} known",
        queries.len()
    );
    let answers = gpu_cell_answers(&gpu, &buffers, &queries);
    let differ = cpu.iter().zip(&answers).filter(|(a, b)| a != b).count();
    assert!(
        differ * 1_000 <= queries.len(),
        "{}: the GPU differs from the CPU on {differ} of {} cells",
        gpu.info.name,
        queries.len()
    );
    // Negative control: the next face's tree answers otherwise for many of them.
    let faces = buffers.faces.len();
    let other = queries
        .iter()
        .zip(&answers)
        .filter(|((f, q, side), a)| cpu_of((*f as usize + 1) % faces, *q, *side) != **a)
        .count();
    assert!(
        other * 10 > queries.len(),
        "another tree agreed on all but {other}"
    );
}

/// The GPU's distance to the trim boundary in pixels (`trim_edge_pixels`, what the trimmed
/// edges' analytic coverage is made of) is its CPU twin's (`TrimBuffers::edge_pixels`) on
/// random points and pixel steps of every face of the bundled assembly and of the sliver,
/// within `f32` rounding. Negative control: the next face's tree gives other distances.
#[test]
fn the_gpu_edge_distance_is_the_cpu_ones() {
    let gpu = common::gpu();
    let (model, _) = common::model_and_scene("pin-assembly.step");
    let mut buffers = model_trees(&model, 0.01).buffers;
    buffers.push(&sliver()).expect("packs");
    let mut random = common::xorshift(0x51_7cc1_b727_220a);
    let mut queries: Vec<(u32, [f32; 2], [f32; 4])> = Vec::new();
    for (face, record) in buffers.faces.iter().enumerate() {
        for _ in 0..1000 {
            let q = [random() * record.size[0], random() * record.size[1]];
            // Pixels of 1/50 to 1/2000 of the face, turned.
            let pixel = record.size[0].max(record.size[1]) / (50.0 + 1950.0 * random());
            let turn = std::f32::consts::TAU * random();
            let (c, s) = (turn.cos(), turn.sin());
            queries.push((
                face as u32,
                q,
                [pixel * c, pixel * s, -pixel * s, pixel * c],
            ));
        }
    }
    let shader = format!(
        "@group(0) @binding(0) var<storage, read> trim_faces: array<TrimFace>;
         @group(0) @binding(1) var<storage, read> trim_nodes: array<u32>;
         @group(0) @binding(2) var<storage, read> trim_floats: array<f32>;
         @group(0) @binding(3) var<storage, read> trim_piece_offsets: array<u32>;
         @group(0) @binding(4) var<storage, read> trim_lists: array<u32>;
         @group(0) @binding(5) var<storage, read> queries: array<vec4<f32>>;
         @group(0) @binding(6) var<storage, read_write> answers: array<f32>;
         {}
         @compute @workgroup_size(64)
         fn main(@builtin(global_invocation_id) id: vec3<u32>) {{
             if 2u * id.x >= arrayLength(&queries) {{ return; }}
             let a = queries[2u * id.x];
             let j = queries[2u * id.x + 1u];
             answers[id.x] = trim_edge_pixels(bitcast<u32>(a.x), a.yz, j.xy, j.zw);
         }}",
        cadre_trim::TRIM_WGSL
    );
    let run = |shift: u32| -> Vec<f32> {
        let faces_count = buffers.faces.len() as u32;
        let words: Vec<f32> = queries
            .iter()
            .flat_map(|(f, q, j)| {
                let face = f32::from_bits((f + shift) % faces_count);
                [face, q[0], q[1], 0.0, j[0], j[1], j[2], j[3]]
            })
            .collect();
        let faces = buffers.face_words();
        let inputs: [&[u8]; 6] = [
            bytemuck::cast_slice(&faces),
            bytemuck::cast_slice(&buffers.nodes),
            bytemuck::cast_slice(&buffers.floats),
            bytemuck::cast_slice(&buffers.piece_offsets),
            bytemuck::cast_slice(&buffers.lists),
            bytemuck::cast_slice(&words),
        ];
        let count = queries.len() as u32;
        let bytes = common::run_compute(&gpu, &shader, &inputs, (count, 4 * u64::from(count)));
        bytemuck::cast_slice(&bytes).to_vec()
    };
    let cpu: Vec<f32> = queries
        .iter()
        .map(|(f, q, j)| {
            let origin = buffers.faces[*f as usize].origin;
            let p = origin + Uv::new(f64::from(q[0]), f64::from(q[1]));
            buffers.edge_pixels(*f as usize, p, [j[0], j[1]], [j[2], j[3]])
        })
        .collect();
    let near = cpu.iter().filter(|&&d| d < 2.0).count();
    assert!(
        near > queries.len() / 50,
        "only {near} of {} points near a boundary",
        queries.len()
    );
    let same = |a: f32, b: f32| (a >= 2.0 && b >= 2.0) || (a - b).abs() <= 1e-3 * (1.0 + a.abs());
    let gpu_out = run(0);
    let differ = cpu
        .iter()
        .zip(&gpu_out)
        .filter(|(a, b)| !same(**a, **b))
        .count();
    assert!(
        differ * 1_000 <= queries.len(),
        "{}: the GPU's distances differ from the CPU's at {differ} of {} points",
        gpu.info.name,
        queries.len()
    );
    let wrong = run(1);
    let differ = cpu
        .iter()
        .zip(&wrong)
        .filter(|(a, b)| !same(**a, **b))
        .count();
    assert!(
        differ * 20 > near,
        "the next face's tree differs at {differ} only"
    );
}
