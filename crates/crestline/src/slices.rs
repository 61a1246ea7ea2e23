//! Compressed rows (offsets plus values, the layout of the mesh's adjacency lists), the
//! cutting of slices into disjoint mutable pieces that lets threads fill them in parallel, and
//! the find step of a union-find forest kept as a slice of parent indices.

/// The root of `i` in a union-find forest stored as parent indices (a root is its own parent),
/// halving the path on the way.
pub(crate) fn union_find_root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Offsets from counts: `[0, c0, c0 + c1, ...]` (one more than the counts).
pub(crate) fn prefix_sums(counts: impl ExactSizeIterator<Item = u32>) -> Vec<u32> {
    let mut offsets = Vec::with_capacity(counts.len() + 1);
    let mut total = 0u32;
    offsets.push(0);
    for c in counts {
        total += c;
        offsets.push(total);
    }
    offsets
}

/// Cuts `values` at `bounds` (increasing, from 0 to at most `values.len()`): one piece per
/// pair of consecutive bounds.
pub(crate) fn split_at<'a, T>(mut values: &'a mut [T], bounds: &[usize]) -> Vec<&'a mut [T]> {
    let mut pieces = Vec::with_capacity(bounds.len().saturating_sub(1));
    for pair in bounds.windows(2) {
        let (piece, rest) = values.split_at_mut(pair[1] - pair[0]);
        pieces.push(piece);
        values = rest;
    }
    pieces
}

/// Cuts `values`, laid out in compressed rows with offsets `offsets`, into pieces of `block`
/// rows each: `(rows, entries of those rows)`, for filling the rows in parallel.
pub(crate) fn split_rows<'a, T>(
    values: &'a mut [T],
    offsets: &[u32],
    block: usize,
) -> Vec<(std::ops::Range<usize>, &'a mut [T])> {
    let rows = offsets.len().saturating_sub(1);
    let firsts: Vec<usize> = (0..rows).step_by(block.max(1)).chain([rows]).collect();
    let bounds: Vec<usize> = firsts
        .iter()
        .map(|&r| (offsets[r] - offsets[0]) as usize)
        .collect();
    firsts
        .windows(2)
        .map(|pair| pair[0]..pair[1])
        .zip(split_at(values, &bounds))
        .collect()
}

/// Compressed rows from (row, value) pairs: offsets of length `rows + 1` and values grouped by
/// row, in the order the pairs came.
pub(crate) fn compressed_rows(
    rows: usize,
    pairs: impl Iterator<Item = (u32, u32)> + Clone,
) -> (Vec<u32>, Vec<u32>) {
    let mut offsets = vec![0u32; rows + 1];
    for (r, _) in pairs.clone() {
        offsets[r as usize + 1] += 1;
    }
    for i in 0..rows {
        offsets[i + 1] += offsets[i];
    }
    let mut cursor = offsets.clone();
    let mut values = vec![0u32; offsets[rows] as usize];
    for (r, x) in pairs {
        let c = &mut cursor[r as usize];
        values[*c as usize] = x;
        *c += 1;
    }
    (offsets, values)
}
