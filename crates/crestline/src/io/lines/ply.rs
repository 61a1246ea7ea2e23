//! Feature lines as PLY vertices and `edge`s with a `kind` and the line's strengths.

use std::io::Write;
use std::path::Path;

use super::{class_of, of_class, read_line};
use crate::error::Result;
use crate::io::ply::edges::{EdgeRecord, parse_edges};
use crate::io::ply::{PlyEncoding, RecordWriter, index_type};
use crate::io::text::Source;
use crate::lines::{FeatureLine, FeatureLines};
use crate::mesh::Vec3;

/// Parses feature lines from a PLY file of vertices and edges (as [`write_lines_ply`] writes
/// them, in any encoding); `name` labels errors.
///
/// # Errors
/// [`Error::Parse`](crate::error::Error::Parse) naming `name` and the position of the fault.
pub fn parse_lines_ply(bytes: &[u8], name: &Path) -> Result<FeatureLines> {
    let source = Source::new(name);
    if bytes.is_empty() {
        return Err(source.whole("empty file"));
    }
    let ply = parse_edges(bytes, source)?;
    if let Some((i, e)) = ply
        .edges
        .iter()
        .enumerate()
        .find(|(_, e)| e.kind.is_some_and(|k| !(0..4).contains(&k)))
    {
        return Err(source.whole(format!(
            "edge {i} has kind {} (known: 0 ridge, 1 valley, 2 crease ridge, 3 crease valley)",
            e.kind.unwrap_or_default()
        )));
    }
    let mut chains: Vec<(usize, FeatureLine)> = Vec::new();
    for class in 0..4 {
        let edges: Vec<(usize, &EdgeRecord)> = ply
            .edges
            .iter()
            .enumerate()
            .filter(|(_, e)| e.kind.unwrap_or(0) as usize == class)
            .collect();
        let (kind, crease) = of_class(class);
        for (first_edge, indices, closed) in chain_edges(&edges, ply.positions.len()) {
            let record = ply.edges[first_edge];
            let points = indices
                .iter()
                .map(|&v| Vec3::from(ply.positions[v as usize]))
                .collect();
            let line = read_line(
                kind,
                crease,
                points,
                closed,
                record.strength.unwrap_or(0.0),
                record.curvature_integral.unwrap_or(0.0),
            );
            chains.push((first_edge, line));
        }
    }
    chains.sort_by_key(|&(first_edge, _)| first_edge);
    Ok(FeatureLines {
        lines: chains.into_iter().map(|(_, l)| l).collect(),
    })
}

/// Chains `edges` (file index, record) into polylines: paths between vertices where other
/// than two edges meet, then loops. Returns, per polyline, the file index of its first edge,
/// its vertices and whether it is closed. A path runs from its lowest-numbered end; a loop
/// starts at the first vertex of its first edge and follows that edge.
fn chain_edges(
    edges: &[(usize, &EdgeRecord)],
    vertex_count: usize,
) -> Vec<(usize, Vec<u32>, bool)> {
    // Edges at each vertex, compressed (offsets, then edge numbers into `edges`).
    let mut start = vec![0usize; vertex_count + 1];
    for (_, e) in edges {
        for v in e.ends {
            start[v as usize + 1] += 1;
        }
    }
    for v in 0..vertex_count {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut at = vec![0usize; 2 * edges.len()];
    for (k, (_, e)) in edges.iter().enumerate() {
        for v in e.ends {
            at[fill[v as usize]] = k;
            fill[v as usize] += 1;
        }
    }
    let degree = |v: u32| start[v as usize + 1] - start[v as usize];
    let mut used = vec![false; edges.len()];
    let other = |k: usize, v: u32| {
        let [a, b] = edges[k].1.ends;
        if a == v { b } else { a }
    };
    // Follows unused edges from `v` over `k` while the path goes through vertices of degree 2.
    let follow = |mut v: u32, mut k: usize, used: &mut Vec<bool>| {
        let mut path = vec![v];
        let mut lowest_edge = edges[k].0;
        loop {
            used[k] = true;
            lowest_edge = lowest_edge.min(edges[k].0);
            v = other(k, v);
            path.push(v);
            if degree(v) != 2 {
                break;
            }
            match at[start[v as usize]..start[v as usize + 1]]
                .iter()
                .find(|&&next| !used[next])
            {
                Some(&next) => k = next,
                None => break,
            }
        }
        (lowest_edge, path)
    };
    let mut polylines = Vec::new();
    for v in 0..vertex_count as u32 {
        if degree(v) == 2 || degree(v) == 0 {
            continue;
        }
        for &k in &at[start[v as usize]..start[v as usize + 1]] {
            if !used[k] {
                let (first, path) = follow(v, k, &mut used);
                polylines.push((first, path, false));
            }
        }
    }
    for k in 0..edges.len() {
        if !used[k] {
            let (first, mut path) = follow(edges[k].1.ends[0], k, &mut used);
            // Around a loop the walk ends where it began.
            let closed = path.len() >= 4 && path.first() == path.last();
            if closed {
                path.pop();
            }
            polylines.push((first, path, closed));
        }
    }
    polylines
}

/// Writes the lines as PLY vertices and `edge`s with a `kind` (0 ridge, 1 valley, 2 crease
/// ridge, 3 crease valley).
///
/// # Errors
/// Whatever `out` returns.
pub fn write_lines_ply<W: Write>(
    out: W,
    lines: &FeatureLines,
    encoding: PlyEncoding,
) -> std::io::Result<()> {
    let vertices: usize = lines.lines.iter().map(|l| l.points.len()).sum();
    let edges: usize = lines
        .lines
        .iter()
        .map(|l| match l.points.len() {
            0 | 1 => 0,
            n if l.closed && n >= 3 => n,
            n => n - 1,
        })
        .sum();
    let index = index_type(vertices);
    let header = format!(
        "ply\nformat {} 1.0\ncomment crestline feature lines; edge kind: 0 = ridge, 1 = valley, 2 = crease ridge, \
         3 = crease valley\n\
         element vertex {vertices}\nproperty double x\nproperty double y\nproperty double z\n\
         element edge {edges}\nproperty {index} vertex1\nproperty {index} vertex2\n\
         property uchar kind\nproperty double strength\nproperty double curvature_integral\n\
         end_header\n",
        encoding.header_name()
    );
    let mut out = RecordWriter::new(out, encoding);
    out.raw(header.as_bytes())?;
    for p in lines.lines.iter().flat_map(|l| &l.points) {
        out.f64(p.x)?;
        out.f64(p.y)?;
        out.f64(p.z)?;
        out.end()?;
    }
    let mut first = 0u32;
    for line in &lines.lines {
        let n = line.points.len() as u32;
        let kind = class_of(line) as u8;
        let closing = line.closed && n >= 3;
        for k in 0..n.saturating_sub(1) + u32::from(closing) {
            out.index(first + k)?;
            out.index(first + (k + 1) % n)?;
            out.u8(kind)?;
            out.f64(line.strength)?;
            out.f64(line.curvature_integral)?;
            out.end()?;
        }
        first += n;
    }
    out.finish()
}
