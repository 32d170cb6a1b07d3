//! Triangle order for vertex reuse: triangles sorted by their lowest vertex index, so that
//! the triangles around a vertex are drawn close together and it is shaded about once.
//!
//! A CPU rasterizer pays for every vertex it shades and clips on the one thread that submits;
//! lavapipe's draw module reuses a shaded vertex only within a window of recent indices (a
//! direct-mapped map of 256 entries over segments of 1,024 indices). The tessellator's order
//! spread a vertex's triangles apart: on the 100× scene (1.1 M triangles) sorting them takes
//! its viewer frame at 1280×960 from 182–192 ms to 172–178 ms (medians, three interleaved
//! rounds). Tom Forsyth's cache optimisation (a 32-entry LRU model; the `meshopt` crate's
//! kind, which could not be fetched on the project's offline machines) did no better here
//! (170–173 ms against the sort's 171–172 in two rounds) at forty times the cost at upload
//! (trj4_pm2, 40 k triangles: +19 ms where the sort takes +0.5), so the sort is kept. The
//! tessellator numbers each face's vertices together, which is what makes the lowest index a
//! good key.

/// Sorts the triangles of `indices` (a triangle list) by their lowest vertex index, keeping
/// the order of ties and each triangle's corners in order (so its winding); a trailing
/// partial triangle stays where it is.
pub(crate) fn optimize(indices: &mut [u32]) {
    let tri_count = indices.len() / 3;
    if tri_count < 2 {
        return;
    }
    let mut tris: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    tris.sort_by_key(|t| t[0].min(t[1]).min(t[2]));
    for (slot, t) in indices.chunks_exact_mut(3).zip(&tris) {
        slot.copy_from_slice(t);
    }
}

/// Vertices shaded per triangle with a `size`-entry FIFO cache (the average cache miss
/// ratio): 3 at worst, 0.5 for a regular grid whose every vertex is shaded once.
#[cfg(test)]
fn acmr(indices: &[u32], size: usize) -> f64 {
    let mut fifo = std::collections::VecDeque::new();
    let mut misses = 0usize;
    for &i in indices {
        if !fifo.contains(&i) {
            misses += 1;
            fifo.push_back(i);
            if fifo.len() > size {
                fifo.pop_front();
            }
        }
    }
    misses as f64 / (indices.len() / 3) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An n × n grid of quads, two triangles each, in a scrambled order.
    fn scrambled_grid(n: u32) -> Vec<u32> {
        let mut tris = Vec::new();
        for y in 0..n {
            for x in 0..n {
                let v = |x: u32, y: u32| y * (n + 1) + x;
                tris.push([v(x, y), v(x + 1, y), v(x + 1, y + 1)]);
                tris.push([v(x, y), v(x + 1, y + 1), v(x, y + 1)]);
            }
        }
        // A fixed permutation far from the grid's order (a prime stride).
        let len = tris.len();
        (0..len).flat_map(|k| tris[(k * 7919) % len]).collect()
    }

    fn sorted_triangles(indices: &[u32]) -> Vec<[u32; 3]> {
        let mut t: Vec<[u32; 3]> = indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        t.sort_unstable();
        t
    }

    #[test]
    fn reordering_keeps_every_triangle_and_its_winding() {
        let mut indices = scrambled_grid(40);
        let before = sorted_triangles(&indices);
        optimize(&mut indices);
        assert_eq!(sorted_triangles(&indices), before);
    }

    #[test]
    fn a_scrambled_mesh_is_shaded_about_once_per_vertex_after() {
        // lavapipe's window: 256 recent indices; a grid of 10,201 vertices.
        let mut indices = scrambled_grid(100);
        let scrambled = acmr(&indices, 256);
        // The control: the scrambled order misses most corners.
        assert!(scrambled > 2.0, "scrambled ACMR {scrambled}");
        optimize(&mut indices);
        let ordered = acmr(&indices, 256);
        assert!(ordered < 0.55, "ordered ACMR {ordered}");
    }

    #[test]
    fn a_trailing_partial_triangle_stays() {
        let mut indices = vec![5, 6, 7, 0, 1, 2, 9];
        optimize(&mut indices);
        assert_eq!(indices, [0, 1, 2, 5, 6, 7, 9]);
    }
}
