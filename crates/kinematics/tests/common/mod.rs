//! The shapes and helpers that the contact tests share.
#![allow(dead_code)]

use moreau_kinematics::{ManifoldPoint, Pose, Shape, collide};

pub fn points(a: &Shape, pa: Pose, b: &Shape, pb: Pose, margin: f64) -> Vec<ManifoldPoint> {
    let mut out = Vec::new();
    collide(a, &pa, b, &pb, margin, &mut out).expect("supported pair");
    out
}

pub fn disk(x: f64, y: f64, r: f64) -> Shape {
    Shape::Disk { center: [x, y], radius: r }
}

pub fn rect(w: f64, h: f64) -> Shape {
    let (a, b) = (w / 2.0, h / 2.0);
    Shape::Polygon { vertices: vec![[-a, -b], [a, -b], [a, b], [-a, b]] }
}

pub fn floor() -> Shape {
    Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] }
}

pub fn sorted_by_feature(mut p: Vec<ManifoldPoint>) -> Vec<ManifoldPoint> {
    p.sort_by_key(|q| q.feature);
    p
}

/// A non-convex cam: r(ψ) = 0.3 + 0.06 cos 3ψ, sampled at 96 points.
pub fn cam() -> Shape {
    Shape::profile_polar(|psi| 0.3 + 0.06 * (3.0 * psi).cos(), 96).expect("valid cam")
}

/// A zigzag guide with concave and convex corners.
pub fn zigzag() -> Shape {
    Shape::Polyline {
        points: vec![[-0.6, 0.0], [-0.3, 0.15], [0.0, -0.05], [0.2, 0.1], [0.45, 0.0], [0.7, 0.2]],
    }
}
