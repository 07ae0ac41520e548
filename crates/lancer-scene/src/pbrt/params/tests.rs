//! Tests of parameter lists: typing, lookups, unused and repeated parameters.

use super::*;
use std::sync::Arc;

fn loc() -> Location {
    Location {
        file: Arc::from("t.pbrt"),
        line: 1,
        col: 1,
    }
}

fn num(t: &str) -> (RawValue, Location) {
    let integral = !t.contains(['.', 'e']);
    (RawValue::Number(t.parse().unwrap(), integral), loc())
}

#[test]
fn types_are_checked_when_read() {
    assert!(Param::new("integer n", loc(), vec![num("1.5")]).is_err());
    assert!(Param::new("integer n", loc(), vec![num("3")]).is_ok());
    assert!(Param::new("rgb c", loc(), vec![num("1"), num("2")]).is_err());
    // A whole number of triples is a colour grid (rgbgrid media): `color` refuses it at the
    // parameter, `rgbs` reads it.
    let six = vec![num("1"), num("2"), num("3"), num("4"), num("5"), num("6")];
    let grid = Param::new("rgb c", loc(), six).unwrap();
    let list = ParamList::new(vec![grid]).unwrap();
    let e = list
        .color(
            "c",
            SpectrumKind::Unbounded,
            &SearchPath::new(std::path::Path::new(".")),
        )
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.pbrt:1:1: \"rgb c\" takes one colour (3 numbers), found 6 numbers"
    );
    let (v, _) = list.rgbs("c").unwrap().unwrap();
    assert_eq!(v, [Rgb::new(1.0, 2.0, 3.0), Rgb::new(4.0, 5.0, 6.0)]);
    assert!(Param::new("floot x", loc(), vec![num("1")]).is_err());
    assert!(Param::new("float", loc(), vec![num("1")]).is_err());
    assert!(Param::new("float x", loc(), vec![]).is_err());
    assert!(Param::new("point3 p", loc(), vec![num("1"), num("2")]).is_err());
    assert!(Param::new("bool b", loc(), vec![(RawValue::Str("true".into()), loc())]).is_ok());
}

#[test]
fn lookups_check_types_and_track_use() {
    let list = ParamList::new(vec![
        Param::new("float radius", loc(), vec![num("2")]).unwrap(),
        Param::new("integer n", loc(), vec![num("2")]).unwrap(),
        Param::new("float unused", loc(), vec![num("2")]).unwrap(),
    ])
    .unwrap();
    assert_eq!(list.float("radius", 1.0).unwrap(), 2.0);
    assert_eq!(list.float("zmin", -1.0).unwrap(), -1.0);
    assert!(list.float("n", 0.0).is_err());
    assert_eq!(list.int("n", 0).unwrap(), 2);
    let mut w = Vec::new();
    list.report_unused("Shape \"sphere\"", &mut w);
    assert_eq!(w.len(), 1);
    assert!(
        w[0].message.contains("\"float unused\""),
        "{}",
        w[0].message
    );
}

#[test]
fn the_last_of_a_parameter_given_twice_counts() {
    let at = |line, col| Location {
        file: Arc::from("t.pbrt"),
        line,
        col,
    };
    let list = ParamList::new(vec![
        Param::new("float radius", at(1, 10), vec![num("0.25")]).unwrap(),
        Param::new("float zmin", at(1, 30), vec![num("-1")]).unwrap(),
        Param::new("float radius", at(2, 3), vec![num("0.5")]).unwrap(),
        Param::new("integer radius", at(3, 3), vec![num("7")]).unwrap(),
    ])
    .unwrap();
    // By name, whatever the type, as pbrt-v4's lookups: the integer is the last.
    assert_eq!(list.int("radius", 1).unwrap(), 7);
    assert!(list.float("radius", 1.0).is_err());
    assert_eq!(list.float("zmin", 0.0).unwrap(), -1.0);
    let mut w = Vec::new();
    list.report_unused("Shape \"sphere\"", &mut w);
    let w: Vec<String> = w.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        w,
        [
            "t.pbrt:1:10: parameter \"float radius\" of Shape \"sphere\" is given again at \
             2:3; this earlier value is ignored (as pbrt-v4, the last one counts)",
            "t.pbrt:2:3: parameter \"float radius\" of Shape \"sphere\" is given again at \
             3:3; this earlier value is ignored (as pbrt-v4, the last one counts)",
        ]
    );
}
