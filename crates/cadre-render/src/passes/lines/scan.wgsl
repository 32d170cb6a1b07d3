// The lines' screen-space arc length: a segmented inclusive scan of the segments' screen
// lengths over the set's points, restarting at every polyline's first point, run every frame
// as three dispatches of one compute pass (blocks, block carries, carries added). Each
// workgroup scans a block of GROUP × PER points; a block records its total and the first
// point in it that starts a polyline, past which the carry from the blocks before does not
// reach.

@group(0) @binding(3) var<storage, read_write> arc: array<f32>;
// Per block: its total (f32 bits; after `scan_carries`, the carry into it) and the index in
// the block of its first polyline start (BLOCK if none).
@group(0) @binding(4) var<storage, read_write> blocks: array<vec2<u32>>;

const GROUP: u32 = 256u;
const PER: u32 = 4u;
const BLOCK: u32 = 1024u;

var<workgroup> sums: array<f32, GROUP>;
var<workgroup> flags: array<u32, GROUP>;
var<workgroup> first_start: atomic<u32>;
var<workgroup> carry: f32;

// The block a workgroup of a (x, y) grid scans (2D past 65,535 blocks).
fn block_of(wg: vec3<u32>, groups: vec3<u32>) -> u32 {
    return wg.x + wg.y * groups.x;
}

// Inclusive segmented scan of (sums, flags) across the workgroup, Hillis–Steele: a value
// whose flag is set does not take the ones before it.
fn scan_group(li: u32) {
    for (var offset = 1u; offset < GROUP; offset <<= 1u) {
        workgroupBarrier();
        var s = sums[li];
        var f = flags[li];
        if (li >= offset) && (f == 0u) {
            s += sums[li - offset];
            f = flags[li - offset];
        }
        workgroupBarrier();
        sums[li] = s;
        flags[li] = f;
    }
    workgroupBarrier();
}

@compute @workgroup_size(256)
fn scan_blocks(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let block = block_of(wg, groups);
    let n = lf.counts.x;
    // The grid's last row may reach past the blocks.
    if block >= lf.counts.y {
        return;
    }
    if li == 0u {
        atomicStore(&first_start, BLOCK);
    }
    workgroupBarrier();
    var values: array<f32, PER>;
    var started: array<bool, PER>;
    var run = 0.0;
    var flag = 0u;
    for (var k = 0u; k < PER; k++) {
        let local = li * PER + k;
        let i = block * BLOCK + local;
        if i < n {
            if starts_polyline(i) {
                run = 0.0;
                flag = 1u;
                atomicMin(&first_start, local);
            }
            run += length_into(i);
        }
        values[k] = run;
        started[k] = flag != 0u;
    }
    sums[li] = run;
    flags[li] = flag;
    scan_group(li);
    // The thread before this one's inclusive value reaches this thread's points up to its
    // first polyline start.
    var before = 0.0;
    if li > 0u {
        before = sums[li - 1u];
    }
    for (var k = 0u; k < PER; k++) {
        let i = block * BLOCK + li * PER + k;
        if i < n {
            arc[i] = values[k] + select(before, 0.0, started[k]);
        }
    }
    if li == GROUP - 1u {
        blocks[block] = vec2<u32>(bitcast<u32>(sums[li]), atomicLoad(&first_start));
    }
}

// One workgroup: the carry into each block, chunk by chunk of GROUP blocks.
@compute @workgroup_size(256)
fn scan_carries(@builtin(local_invocation_index) li: u32) {
    // Bounded by the buffer too (see `section_cut`, common.wgsl, on loops bounded by a
    // uniform alone).
    let count = min(lf.counts.y, arrayLength(&blocks));
    if li == 0u {
        carry = 0.0;
    }
    for (var start = 0u; start < count; start += GROUP) {
        let b = start + li;
        var total = 0.0;
        var flag = 0u;
        if b < count {
            total = bitcast<f32>(blocks[b].x);
            flag = select(0u, 1u, blocks[b].y < BLOCK);
        }
        sums[li] = total;
        flags[li] = flag;
        scan_group(li);
        // Exclusive: what the blocks before `b` carry into it.
        var into = carry;
        if li > 0u {
            into = select(carry + sums[li - 1u], sums[li - 1u], flags[li - 1u] != 0u);
        }
        if b < count {
            blocks[b].x = bitcast<u32>(into);
        }
        workgroupBarrier();
        if li == GROUP - 1u {
            carry = select(carry + sums[li], sums[li], flags[li] != 0u);
        }
        workgroupBarrier();
    }
}

@compute @workgroup_size(256)
fn scan_add(
    @builtin(workgroup_id) wg: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) li: u32,
) {
    let block = block_of(wg, groups);
    let n = lf.counts.x;
    if block >= lf.counts.y {
        return;
    }
    let record = blocks[block];
    let into = bitcast<f32>(record.x);
    for (var k = 0u; k < PER; k++) {
        let local = li * PER + k;
        let i = block * BLOCK + local;
        if (i < n) & (local < record.y) {
            arc[i] += into;
        }
    }
}
