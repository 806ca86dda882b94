//! Geometry in plot coordinates: lines and polygons clipped to the plotting area, and
//! the pixel boxes labels claim so that none is drawn over another.

/// The part of the segment a–b inside the box [x0, x1] × [y0, y1] (Liang–Barsky), or
/// `None` when it lies outside: lines are clipped to the plotting area, never drawn on
/// its edge.
pub fn clip_segment(a: (f64, f64), b: (f64, f64), x: (f64, f64), y: (f64, f64)) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [(-dx, a.0 - x.0), (dx, x.1 - a.0), (-dy, a.1 - y.0), (dy, y.1 - a.1)] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0.partial_cmp(&t1) == Some(std::cmp::Ordering::Greater) || t0.is_nan() || t1.is_nan() {
        return None;
    }
    Some(((a.0 + t0 * dx, a.1 + t0 * dy), (a.0 + t1 * dx, a.1 + t1 * dy)))
}

/// A polyline clipped to the box: the pieces inside it, each a polyline.
pub fn clip_polyline(points: &[(f64, f64)], x: (f64, f64), y: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let finite = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    if points.len() == 1 && finite(&points[0]) {
        let p = points[0];
        if p.0 >= x.0 && p.0 <= x.1 && p.1 >= y.0 && p.1 <= y.1 {
            return vec![vec![p]];
        }
    }
    for w in points.windows(2) {
        if !finite(&w[0]) || !finite(&w[1]) {
            if cur.len() > 1 {
                out.push(std::mem::take(&mut cur));
            }
            cur.clear();
            continue;
        }
        match clip_segment(w[0], w[1], x, y) {
            Some((p, q)) => {
                if cur.last() != Some(&p) {
                    if cur.len() > 1 {
                        out.push(std::mem::take(&mut cur));
                    }
                    cur = vec![p];
                }
                cur.push(q);
            }
            None => {
                if cur.len() > 1 {
                    out.push(std::mem::take(&mut cur));
                }
                cur.clear();
            }
        }
    }
    if cur.len() > 1 {
        out.push(cur);
    }
    out
}

/// A polygon clipped to the box (Sutherland–Hodgman; the box is convex).
pub fn clip_polygon(points: &[(f64, f64)], x: (f64, f64), y: (f64, f64)) -> Vec<(f64, f64)> {
    let mut poly: Vec<(f64, f64)> = points.to_vec();
    // The four half-planes of the box: (axis 0 = x / 1 = y, bound, keep the side above).
    for (axis, bound, above) in [(0, x.0, true), (0, x.1, false), (1, y.0, true), (1, y.1, false)] {
        if poly.is_empty() {
            break;
        }
        let inside = |p: (f64, f64)| {
            let v = if axis == 0 { p.0 } else { p.1 };
            if above {
                v >= bound
            } else {
                v <= bound
            }
        };
        let cut = |a: (f64, f64), b: (f64, f64)| if axis == 0 { at_x(a, b, bound) } else { at_y(a, b, bound) };
        let input = std::mem::take(&mut poly);
        for i in 0..input.len() {
            let (cur, prev) = (input[i], input[(i + input.len() - 1) % input.len()]);
            match (inside(cur), inside(prev)) {
                (true, true) => poly.push(cur),
                (true, false) => {
                    poly.push(cut(prev, cur));
                    poly.push(cur);
                }
                (false, true) => poly.push(cut(prev, cur)),
                (false, false) => {}
            }
        }
    }
    poly
}

fn at_x(a: (f64, f64), b: (f64, f64), x: f64) -> (f64, f64) {
    let t = (x - a.0) / (b.0 - a.0);
    (x, a.1 + t * (b.1 - a.1))
}

fn at_y(a: (f64, f64), b: (f64, f64), y: f64) -> (f64, f64) {
    let t = (y - a.1) / (b.1 - a.1);
    (a.0 + t * (b.0 - a.0), y)
}

/// Axis-aligned pixel boxes that do not overlap one another: a label placed only if its
/// box is free (labels that would collide are skipped rather than piled up).
#[derive(Debug, Default)]
pub struct Occupied(Vec<[(i32, i32); 2]>);

impl Occupied {
    /// Reserve `b` if it overlaps nothing reserved; whether it was free.
    pub fn claim(&mut self, b: [(i32, i32); 2]) -> bool {
        let overlaps = |o: &[(i32, i32); 2]| b[0].0 < o[1].0 && o[0].0 < b[1].0 && b[0].1 < o[1].1 && o[0].1 < b[1].1;
        if self.0.iter().any(overlaps) {
            return false;
        }
        self.0.push(b);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_keeps_lines_inside() {
        let (x, y) = ((0.0, 10.0), (0.0, 1.0));
        assert_eq!(clip_segment((-5.0, 0.5), (5.0, 0.5), x, y), Some(((0.0, 0.5), (5.0, 0.5))));
        assert_eq!(clip_segment((11.0, 0.5), (12.0, 0.9), x, y), None);
        // A boundary beyond the right edge is dropped, not drawn along the axis.
        assert!(clip_polyline(&[(12.0, 0.0), (13.0, 0.5), (12.5, 1.0)], x, y).is_empty());
        let pieces = clip_polyline(&[(5.0, 0.5), (15.0, 0.5), (15.0, 0.7), (5.0, 0.7)], x, y);
        assert_eq!(pieces, vec![vec![(5.0, 0.5), (10.0, 0.5)], vec![(10.0, 0.7), (5.0, 0.7)]]);
        let square = clip_polygon(&[(5.0, 0.5), (15.0, 0.5), (15.0, 2.0), (5.0, 2.0)], x, y);
        assert!(square.iter().all(|p| p.0 >= 5.0 && p.0 <= 10.0 && p.1 >= 0.5 && p.1 <= 1.0), "{square:?}");
        assert!(clip_polygon(&[(12.0, 0.5), (15.0, 0.5), (15.0, 2.0)], x, y).is_empty());
    }

    #[test]
    fn occupied_boxes_refuse_overlaps() {
        let mut o = Occupied::default();
        assert!(o.claim([(0, 0), (10, 10)]));
        assert!(!o.claim([(5, 5), (15, 15)]));
        assert!(o.claim([(10, 0), (20, 10)]));
    }
}
