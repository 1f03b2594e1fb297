//! The colours of curves, one per method, shared by the study's plots and the viewer's relMSE
//! plot: matplotlib's tab10 in its order (a qualitative palette whose ten entries are told apart
//! at a glance), then the same ten again with dashed lines (and hollow markers in the study's).

/// matplotlib's tab10, in order.
pub const TAB10: [[u8; 3]; 10] = [
    [31, 119, 180],  // blue
    [255, 127, 14],  // orange
    [44, 160, 44],   // green
    [214, 39, 40],   // red
    [148, 103, 189], // purple
    [140, 86, 75],   // brown
    [227, 119, 194], // pink
    [127, 127, 127], // grey
    [188, 189, 34],  // olive
    [23, 190, 207],  // cyan
];

/// How the `i`-th curve is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CurveStyle {
    pub rgb: [u8; 3],
    /// Dashed where the curves outnumber the colours (from the 11th on).
    pub dashed: bool,
}

/// The style of curve `i` (0-based).
pub fn curve_style(i: usize) -> CurveStyle {
    CurveStyle { rgb: TAB10[i % TAB10.len()], dashed: i >= TAB10.len() }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CIE L*a*b* of an sRGB colour (D65).
    fn lab(rgb: [u8; 3]) -> [f64; 3] {
        let lin = |c: u8| {
            let c = c as f64 / 255.0;
            if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
        };
        let (r, g, b) = (lin(rgb[0]), lin(rgb[1]), lin(rgb[2]));
        let x = (0.4124 * r + 0.3576 * g + 0.1805 * b) / 0.95047;
        let y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
        let z = (0.0193 * r + 0.1192 * g + 0.9505 * b) / 1.08883;
        let f = |t: f64| if t > 216.0 / 24389.0 { t.cbrt() } else { (24389.0 / 27.0 * t + 16.0) / 116.0 };
        [116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z))]
    }

    /// Every two of the ten colours are at least 20 CIE76 units apart (about ten times a
    /// just-noticeable difference; tab10's closest pair, purple and pink, is 27.7 apart), and
    /// no two of the first 20 curves share a style.
    #[test]
    fn every_curve_can_be_told_from_every_other() {
        for i in 0..TAB10.len() {
            for j in 0..i {
                let (a, b) = (lab(TAB10[i]), lab(TAB10[j]));
                let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
                assert!(d >= 20.0, "curves {i} and {j} are {d:.1} CIE76 units apart");
            }
        }
        let styles: std::collections::HashSet<CurveStyle> = (0..20).map(curve_style).collect();
        assert_eq!(styles.len(), 20);
    }
}
