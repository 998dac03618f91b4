//! Level lines of a field on a rectangular grid by marching squares (for the paper's Fig. 25
//! transition contour on parameter maps).
//!
//! The grid has nodes `(xs[i], ys[j])` (any spacing) with values `z[j·nx + i]`. Each grid square
//! whose four corners are finite is classified by which corners are `≥ level`; the crossing
//! points on its edges are found by linear interpolation, and one or two segments join them.
//! The two saddle cases are resolved by the mean of the corners (the centre value). Squares with
//! a NaN corner are skipped (no line through missing data).

/// A segment `[(x, y), (x, y)]` of a level line.
pub type Segment = [(f64, f64); 2];

/// Segments of the line `z = level` (square by square, row-major order: deterministic).
pub fn marching_squares(xs: &[f64], ys: &[f64], z: &[f64], level: f64) -> Vec<Segment> {
    let (nx, ny) = (xs.len(), ys.len());
    let mut out = Vec::new();
    if nx < 2 || ny < 2 || z.len() != nx * ny || !level.is_finite() {
        return out;
    }
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            // corners counter-clockwise from bottom-left: (i,j), (i+1,j), (i+1,j+1), (i,j+1)
            let p = [
                (xs[i], ys[j]),
                (xs[i + 1], ys[j]),
                (xs[i + 1], ys[j + 1]),
                (xs[i], ys[j + 1]),
            ];
            let v = [
                z[j * nx + i],
                z[j * nx + i + 1],
                z[(j + 1) * nx + i + 1],
                z[(j + 1) * nx + i],
            ];
            if v.iter().any(|x| !x.is_finite()) {
                continue;
            }
            let above: Vec<bool> = v.iter().map(|&x| x >= level).collect();
            // crossing on edge e (between corners e and e+1), if its ends differ
            let cross = |e: usize| -> Option<(f64, f64)> {
                let (a, b) = (e, (e + 1) % 4);
                if above[a] == above[b] {
                    return None;
                }
                let f = (level - v[a]) / (v[b] - v[a]);
                Some((
                    p[a].0 + f * (p[b].0 - p[a].0),
                    p[a].1 + f * (p[b].1 - p[a].1),
                ))
            };
            let c: Vec<(usize, (f64, f64))> =
                (0..4).filter_map(|e| cross(e).map(|q| (e, q))).collect();
            match c.len() {
                2 => out.push([c[0].1, c[1].1]),
                4 => {
                    // saddle: corners 0 and 2 on one side, 1 and 3 on the other
                    let centre = (v[0] + v[1] + v[2] + v[3]) / 4.0;
                    let q: Vec<(f64, f64)> = c.iter().map(|x| x.1).collect();
                    if (centre >= level) == above[0] {
                        // the centre joins corner 0's region: cut off corners 1 and 3
                        out.push([q[0], q[1]]);
                        out.push([q[2], q[3]]);
                    } else {
                        // cut off corners 0 and 2
                        out.push([q[3], q[0]]);
                        out.push([q[1], q[2]]);
                    }
                }
                _ => {}
            }
        }
    }
    out
}
