//! A declared shape's validation, refused by the field at fault: the shape is valid when
//! `moreau_kinematics::Shape::validate` passes it, and a refusal names the shape's field (its
//! `radius`, its vertex `vertices.2`, its `normal`) with that field's value and what is wrong.

use moreau_kinematics::{KinematicsError, Shape};

use super::build::bad;
use crate::ModelError;
use crate::params::{finite, non_negative};

/// A point as written in a message: `[0.1, -0.05]`.
fn point(p: [f64; 2]) -> String {
    format!("[{}, {}]", p[0], p[1])
}

/// A list of points as written in a message.
fn points(list: &[[f64; 2]]) -> String {
    format!("[{}]", list.iter().map(|&p| point(p)).collect::<Vec<_>>().join(", "))
}

/// Twice the signed area of the closed chain through `list` (positive counter-clockwise).
fn signed_area2(list: &[[f64; 2]]) -> f64 {
    let n = list.len();
    (0..n)
        .map(|i| {
            let ([x0, y0], [x1, y1]) = (list[i], list[(i + 1) % n]);
            x0 * y1 - x1 * y0
        })
        .sum()
}

/// Checks `shape`, the shape at `path` (`bodies.<name>.shapes.<k>`, `fill.<name>.shape`).
///
/// # Errors
/// [`ModelError::InvalidParameter`] for a number out of range (`<path>.radius`, a coordinate
/// `<path>.center.0` that is not finite), [`ModelError::BadValue`] for a point or a list of
/// points (`<path>.vertices.2`, `<path>.vertices`, `<path>.normal`), each naming what is wrong.
pub(crate) fn check_shape(path: &str, shape: &Shape) -> Result<(), ModelError> {
    let Err(error) = shape.validate() else { return Ok(()) };
    let field = |f: &str| format!("{path}.{f}");
    let finite2 = |f: &str, p: [f64; 2]| {
        finite(&format!("{path}.{f}.0"), p[0])?;
        finite(&format!("{path}.{f}.1"), p[1])
    };
    // The vertex or point that the kinematics' refusal names, if it names one.
    let index = match &error {
        KinematicsError::InvalidShape { index, .. } => *index,
        _ => None,
    };
    match shape {
        Shape::Disk { center, radius } => {
            finite2("center", *center)?;
            non_negative(&field("radius"), *radius)?;
        }
        Shape::Capsule { a, b, radius } => {
            finite2("a", *a)?;
            finite2("b", *b)?;
            if a == b {
                return Err(bad(
                    field("b"),
                    &point(*b),
                    "is the capsule's other end `a` too: its two ends must differ (a disk has \
                     one centre)"
                        .to_owned(),
                ));
            }
            non_negative(&field("radius"), *radius)?;
        }
        Shape::HalfPlane { point: p, normal } => {
            finite2("point", *p)?;
            finite2("normal", *normal)?;
            let why = if *normal == [0.0; 2] {
                "must not be zero: it is the direction out of the solid"
            } else {
                "is too small or too large to be made a unit vector (its length must lie in \
                 about 1.5e-154 to 1.3e154); any length in between does"
            };
            return Err(bad(field("normal"), &point(*normal), why.to_owned()));
        }
        Shape::Polyline { points: list } => chain(path, "points", list, 2, false)?,
        Shape::Polygon { vertices } => {
            chain(path, "vertices", vertices, 3, true)?;
            let mut reversed = vertices.clone();
            reversed.reverse();
            let turned = Shape::Polygon { vertices: reversed.clone() };
            if signed_area2(vertices) < 0.0 && turned.validate().is_ok() {
                return Err(bad(
                    field("vertices"),
                    &points(vertices),
                    format!(
                        "the vertices run clockwise; a polygon lists them counter-clockwise: {}",
                        points(&reversed)
                    ),
                ));
            }
            if let Some(i) = index {
                return Err(bad(
                    format!("{path}.vertices.{i}"),
                    &point(vertices[i]),
                    format!(
                        "the polygon {} at this vertex, so it is not strictly convex with its \
                         vertices counter-clockwise; a non-convex body takes several convex \
                         polygons",
                        if signed_area2(vertices) > 0.0 {
                            "turns clockwise or goes straight on"
                        } else {
                            "does not turn counter-clockwise"
                        }
                    ),
                ));
            }
            return Err(bad(
                field("vertices"),
                &points(vertices),
                "the vertices wind round more than once (a star); a polygon goes round once"
                    .to_owned(),
            ));
        }
        Shape::Profile { points: list } => {
            chain(path, "points", list, 3, true)?;
            if !(signed_area2(list) > 0.0) {
                return Err(bad(
                    field("points"),
                    &points(list),
                    "the points run clockwise or enclose no area; a profile lists them \
                     counter-clockwise round its solid"
                        .to_owned(),
                ));
            }
            if let Some(j) = index {
                return Err(bad(
                    format!("{path}.points.{j}"),
                    &point(list[j]),
                    format!(
                        "the contour crosses itself: the segment from this point to point {} \
                         meets another",
                        (j + 1) % list.len()
                    ),
                ));
            }
        }
    }
    // A refusal the fields above do not explain keeps the kinematics' words.
    Err(bad(path.to_owned(), shape.name(), error.to_string()))
}

/// Checks the chain of points `list` of the field `name` of the shape at `path`: at least
/// `min` points, each finite, no two consecutive ones equal (the last and the first too when
/// `closed`).
fn chain(
    path: &str,
    name: &str,
    list: &[[f64; 2]],
    min: usize,
    closed: bool,
) -> Result<(), ModelError> {
    if list.len() < min {
        return Err(bad(
            format!("{path}.{name}"),
            &points(list),
            format!("{} points, where the shape needs at least {min}", list.len()),
        ));
    }
    for (i, p) in list.iter().enumerate() {
        finite(&format!("{path}.{name}.{i}.0"), p[0])?;
        finite(&format!("{path}.{name}.{i}.1"), p[1])?;
    }
    let n = list.len();
    let segments = if closed { n } else { n - 1 };
    if let Some(i) = (0..segments).find(|&i| list[i] == list[(i + 1) % n]) {
        let next = (i + 1) % n;
        return Err(bad(
            format!("{path}.{name}.{next}"),
            &point(list[next]),
            format!("repeats point {i}: consecutive points must differ"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn refusal(shape: Shape) -> String {
        check_shape("bodies.b.shapes.0", &shape).unwrap_err().to_string()
    }

    #[test]
    fn each_shape_is_refused_by_its_field() {
        let square = vec![[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]];
        assert!(check_shape("s", &Shape::Polygon { vertices: square.clone() }).is_ok());
        assert_eq!(
            refusal(Shape::Disk { center: [0.0, 0.0], radius: -0.1 }),
            "invalid parameter `bodies.b.shapes.0.radius` = -0.1: must be finite and >= 0"
        );
        assert_eq!(
            refusal(Shape::Disk { center: [0.0, f64::NAN], radius: 0.1 }),
            "invalid parameter `bodies.b.shapes.0.center.1` = NaN: must be finite"
        );
        let mut clockwise = square.clone();
        clockwise.reverse();
        assert_eq!(
            refusal(Shape::Polygon { vertices: clockwise }),
            "bad value `[[-0.1, 0.1], [0.1, 0.1], [0.1, -0.1], [-0.1, -0.1]]` for \
             `bodies.b.shapes.0.vertices`: the vertices run clockwise; a polygon lists them \
             counter-clockwise: [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]"
        );
        let dented = vec![[-0.1, -0.1], [0.1, -0.1], [0.0, 0.0], [0.1, 0.1], [-0.1, 0.1]];
        assert!(refusal(Shape::Polygon { vertices: dented }).starts_with(
            "bad value `[0, 0]` for `bodies.b.shapes.0.vertices.2`: the polygon turns clockwise"
        ));
        let repeated = vec![[-0.1, -0.1], [0.1, -0.1], [0.1, -0.1], [-0.1, 0.1]];
        assert_eq!(
            refusal(Shape::Polygon { vertices: repeated }),
            "bad value `[0.1, -0.1]` for `bodies.b.shapes.0.vertices.2`: repeats point 1: \
             consecutive points must differ"
        );
        assert_eq!(
            refusal(Shape::Polygon { vertices: square[..2].to_vec() }),
            "bad value `[[-0.1, -0.1], [0.1, -0.1]]` for `bodies.b.shapes.0.vertices`: 2 \
             points, where the shape needs at least 3"
        );
        assert_eq!(
            refusal(Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 0.0] }),
            "bad value `[0, 0]` for `bodies.b.shapes.0.normal`: must not be zero: it is the \
             direction out of the solid"
        );
        assert_eq!(
            refusal(Shape::Capsule { a: [0.0, 0.0], b: [0.0, 0.0], radius: 0.1 }),
            "bad value `[0, 0]` for `bodies.b.shapes.0.b`: is the capsule's other end `a` \
             too: its two ends must differ (a disk has one centre)"
        );
        let star = (0..5)
            .map(|k| {
                let a = k as f64 * 4.0 * std::f64::consts::PI / 5.0;
                [a.cos(), a.sin()]
            })
            .collect::<Vec<_>>();
        assert!(refusal(Shape::Polygon { vertices: star }).contains("wind round more than once"));
        let bow = vec![[0.0, 0.0], [3.0, 0.0], [3.0, 3.0], [1.0, -1.0], [0.0, 3.0]];
        let text = refusal(Shape::Profile { points: bow });
        assert!(text.contains("the contour crosses itself"), "{text}");
    }
}
