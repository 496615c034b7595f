//! Conduit cross-sections of the SWMM model and the open-channel hydraulics of one section:
//! wetted area, hydraulic radius and top width at a flow depth, full-section values, critical
//! depth, Manning's normal flow and normal depth (SI units: metres, m³/s).
//!
//! karstgen's conduit types map to SWMM's closed shapes: `canyon` a closed rectangle 2r high
//! and 1.2r wide, `bed` (bedding plane) a closed rectangle 0.9r high and 2.4r wide, every other
//! type a circle of diameter 2r. The formulas are the textbook ones (Chow 1959) for the shapes
//! SWMM uses, so that the steady state computed here (steady.rs) is the one SWMM's engine finds.

use std::f64::consts::PI;

use karst_skeleton::ConduitType;

/// Gravity, m/s².
pub const GRAVITY: f64 = 9.81;

/// A closed SWMM shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    Circular,
    RectClosed,
}

/// A cross-section: shape, full height and (rectangles) width, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    pub shape: Shape,
    pub height: f64,
    pub width: f64,
}

impl Section {
    /// The section of a conduit of type `kind` and radius `r`.
    pub fn of(kind: ConduitType, r: f64) -> Section {
        match kind {
            ConduitType::Canyon => Section::rect(2.0 * r, 1.2 * r),
            ConduitType::Bed => Section::rect(0.9 * r, 2.4 * r),
            _ => Section::circle(2.0 * r),
        }
    }

    pub fn circle(diameter: f64) -> Section {
        Section { shape: Shape::Circular, height: diameter, width: 0.0 }
    }

    pub fn rect(height: f64, width: f64) -> Section {
        Section { shape: Shape::RectClosed, height, width }
    }

    /// The section with its dimensions rounded as they are written (4 decimals).
    pub fn rounded(&self) -> Section {
        let round = |x: f64| (x * 1e4).round() / 1e4;
        Section { shape: self.shape, height: round(self.height), width: round(self.width) }
    }

    /// SWMM's `[XSECTIONS]` shape keyword.
    pub fn keyword(&self) -> &'static str {
        match self.shape {
            Shape::Circular => "CIRCULAR",
            Shape::RectClosed => "RECT_CLOSED",
        }
    }

    /// The same shape scaled to the full area `area`.
    pub fn with_full_area(&self, area: f64) -> Section {
        let k = (area / self.full_area()).sqrt();
        Section { shape: self.shape, height: self.height * k, width: self.width * k }
    }

    /// Central angle of the wetted part of a circle at depth `y`.
    fn angle(&self, y: f64) -> f64 {
        2.0 * (1.0 - 2.0 * y / self.height).clamp(-1.0, 1.0).acos()
    }

    pub fn full_area(&self) -> f64 {
        match self.shape {
            Shape::Circular => PI * self.height * self.height / 4.0,
            Shape::RectClosed => self.height * self.width,
        }
    }

    /// Wetted area at depth `y` (the full area above the crown: no Preissmann slot).
    pub fn area(&self, y: f64) -> f64 {
        let y = y.clamp(0.0, self.height);
        match self.shape {
            Shape::Circular => {
                let t = self.angle(y);
                self.height * self.height / 8.0 * (t - t.sin())
            }
            Shape::RectClosed => self.width * y,
        }
    }

    fn perimeter(&self, y: f64) -> f64 {
        let y = y.clamp(0.0, self.height);
        match self.shape {
            Shape::Circular => self.height * self.angle(y) / 2.0,
            Shape::RectClosed if y >= self.height => 2.0 * (self.width + self.height),
            Shape::RectClosed => self.width + 2.0 * y,
        }
    }

    /// Hydraulic radius at depth `y` (0 when dry).
    pub fn hydraulic_radius(&self, y: f64) -> f64 {
        let p = self.perimeter(y);
        if p > 0.0 { self.area(y) / p } else { 0.0 }
    }

    /// Width of the free surface at depth `y` (0 when full).
    pub fn top_width(&self, y: f64) -> f64 {
        if y <= 0.0 || y >= self.height {
            return 0.0;
        }
        match self.shape {
            Shape::Circular => self.height * (self.angle(y) / 2.0).sin(),
            Shape::RectClosed => self.width,
        }
    }

    /// Froude number of a flow at velocity `v` and depth `y` (0 when dry or full).
    pub fn froude(&self, v: f64, y: f64) -> f64 {
        let w = self.top_width(y);
        if w <= 0.0 || y <= 0.0 {
            return 0.0;
        }
        v.abs() / (GRAVITY * self.area(y) / w).sqrt()
    }

    /// Manning's normal flow at depth `y` on slope `slope` (its absolute value, as SWMM).
    pub fn normal_flow(&self, y: f64, slope: f64, manning: f64) -> f64 {
        self.area(y) * self.hydraulic_radius(y).powf(2.0 / 3.0) * slope.abs().sqrt() / manning
    }

    /// Depth at which the normal flow is `q`; the full height when the section cannot carry
    /// it at this slope (flowing full) or the slope is not downhill.
    pub fn normal_depth(&self, q: f64, slope: f64, manning: f64) -> f64 {
        let full = 0.999 * self.height;
        if slope <= 0.0 || self.normal_flow(full, slope, manning) < q {
            return self.height;
        }
        bisect(0.0, full, |y| self.normal_flow(y, slope, manning) < q)
    }

    /// Depth at which a flow `q` is critical (Froude 1); the full height when it never is.
    pub fn critical_depth(&self, q: f64) -> f64 {
        let critical = |y: f64| {
            let a = self.area(y);
            a > 0.0 && q * q * self.top_width(y) >= GRAVITY * a * a * a
        };
        bisect(0.0, self.height, critical)
    }
}

/// The boundary in `[lo, hi]` between where `below` holds (low end) and where it does not.
pub fn bisect(mut lo: f64, mut hi: f64, below: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if below(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_areas_radii_and_widths() {
        let c = Section::circle(2.0);
        assert!((c.area(1.0) - PI / 2.0).abs() < 1e-12, "half full");
        assert!((c.area(2.0) - PI).abs() < 1e-12);
        assert!((c.hydraulic_radius(1.0) - 0.5).abs() < 1e-12, "D/4 half full");
        assert!((c.top_width(1.0) - 2.0).abs() < 1e-12);
        assert_eq!(c.top_width(2.0), 0.0);
    }

    #[test]
    fn rectangle_critical_and_normal_depths() {
        let r = Section::rect(4.0, 10.0);
        // critical depth of a rectangle: (q²/(g b²))^(1/3)
        let yc = r.critical_depth(1.0);
        assert!((yc - (1.0 / (GRAVITY * 100.0)).cbrt()).abs() < 1e-9, "{yc}");
        // normal depth: the flow at it is the asked flow
        let yn = r.normal_depth(1.0, 0.05, 0.03);
        assert!((r.normal_flow(yn, 0.05, 0.03) - 1.0).abs() < 1e-9);
        assert!(yn < yc, "a 5 % slope is steep for 1 m³/s in a 10 m wide channel");
        assert_eq!(r.normal_depth(1e6, 0.05, 0.03), 4.0, "too much water: full");
        assert_eq!(r.normal_depth(1.0, -0.01, 0.03), 4.0, "uphill: no normal depth");
    }

    #[test]
    fn scaling_keeps_the_shape() {
        let r = Section::rect(2.0, 1.0).with_full_area(8.0);
        assert!((r.height - 4.0).abs() < 1e-12 && (r.width - 2.0).abs() < 1e-12);
    }
}
