//! The inputs layer of previews: every input of a scene becomes a mark of its role, island hills
//! as the operations leave them, and marks land where their world coordinates say.

use glam::DVec2;
use relief::Scene;
use relief::heightfield::Extent;
use relief::io::RgbImage;
use relief::overlay::{Mark, Role, draw_marks, scene_marks, scene_sea_level};

fn scene(generator: &serde_json::Value) -> Scene {
    let json =
        serde_json::json!({ "version": 1, "domain": { "min": [0, 0], "max": [100, 100] }, "generator": generator });
    Scene::from_json(&json.to_string()).unwrap()
}

fn roles(marks: &[Mark]) -> Vec<Role> {
    marks.iter().map(|m| m.role).collect()
}

#[test]
fn contour_regions_are_marked_by_nesting_and_kind() {
    let square = |lo: f64, hi: f64| serde_json::json!({ "exterior": [[lo, lo], [hi, lo], [hi, hi], [lo, hi]] });
    let s = scene(&serde_json::json!({ "contours": { "regions": [
        { "polygon": square(10.0, 90.0), "height": 0.0 },
        { "polygon": square(20.0, 50.0), "height": 100.0 },
        { "polygon": square(30.0, 40.0), "depression": true },
    ] } }));
    let marks = scene_marks(&s);
    assert_eq!(roles(&marks), [Role::Coastline, Role::Raised, Role::Depression]);
    assert!(marks.iter().all(|m| m.closed && m.points.len() == 4));
    assert_eq!(marks[1].points[0], DVec2::new(20.0, 20.0));
    // The coastline's height is the sea level a preview draws, wherever it is listed.
    assert_eq!(scene_sea_level(&s), Some(0.0));
    let inner_first = scene(&serde_json::json!({ "contours": { "regions": [
        { "polygon": square(20.0, 50.0), "height": 100.0 },
        { "polygon": square(10.0, 90.0), "height": 5.0 },
    ] } }));
    assert_eq!(scene_sea_level(&inner_first), Some(5.0));
}

#[test]
fn island_hills_are_drawn_as_the_operations_leave_them() {
    let s = scene(&serde_json::json!({ "island": { "operations": [
        { "stroke": { "points": [[5, -1], [5, 101]] } },
        { "add_hill": { "center": [30, 30], "radii": [10, 5], "height": 50 } },
        { "add_hill": { "center": [60, 60], "radii": [8, 8], "height": 20 } },
        { "move_hill": { "hill": 0, "center": [40, 30] } },
        { "resize_hill": { "hill": 0, "radii": [12, 6], "rotation": 90 } },
        { "remove_hill": { "hill": 1 } },
    ] } }));
    let marks = scene_marks(&s);
    // The stroke's start dot, the stroke, then the one hill left: its centre and its ellipse.
    assert_eq!(roles(&marks), [Role::Stroke, Role::Stroke, Role::Hill, Role::Hill]);
    assert_eq!(marks[0].points, [DVec2::new(5.0, -1.0)]);
    assert_eq!(marks[2].points, [DVec2::new(40.0, 30.0)]);
    // Turned by 90°, the 12 m semi-axis runs north-south.
    let ring = &marks[3].points;
    let (lo, hi) = ring.iter().fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    assert!(((hi - lo) - DVec2::new(12.0, 24.0)).abs().max_element() < 0.1, "{lo} {hi}");
    // Half the land floor (default 0.1) separates sea from land.
    assert_eq!(scene_sea_level(&s), Some(0.05));
    // A new coastline is drawn as one; a hill index past the end (the island refuses it when
    // generating) changes nothing here.
    let s = scene(&serde_json::json!({ "island": { "operations": [
        { "coastline": { "points": [[10, 10], [90, 10], [50, 90]] } },
        { "add_hill": { "center": [50, 40], "radii": [10, 10], "height": 5 } },
        { "remove_hill": { "hill": 1 } },
    ] } }));
    let marks = scene_marks(&s);
    assert_eq!(roles(&marks), [Role::Coastline, Role::Hill, Role::Hill]);
    assert!(marks[0].closed && marks[0].points.len() == 3);
}

#[test]
fn diffusion_curves_and_orometry_peaks_are_marked() {
    let s = scene(&serde_json::json!({ "diffusion": { "curves": [
        { "points": [[10, 10], [90, 90]], "constraints": [{ "u": 0, "elevation": { "h": 10, "r": 0 } }] },
    ] } }));
    let marks = scene_marks(&s);
    assert_eq!(roles(&marks), [Role::Curve]);
    let line = &marks[0].points;
    assert_eq!((line[0], line[line.len() - 1]), (DVec2::splat(10.0), DVec2::splat(90.0)));
    assert!(line.len() > 100, "the curve is drawn finely: {} points", line.len());
    assert_eq!(scene_sea_level(&s), None);
}

fn grey(n: usize) -> RgbImage {
    RgbImage { width: n, height: n, pixels: vec![128; n * n * 3] }
}

fn pixel(image: &RgbImage, x: usize, y: usize) -> [u8; 3] {
    let k = 3 * (y * image.width + x);
    [image.pixels[k], image.pixels[k + 1], image.pixels[k + 2]]
}

#[test]
fn marks_land_where_their_coordinates_say_in_their_colour_over_a_halo() {
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(100.0));
    let mut image = grey(101);
    // A west-east line at y = 75 (a quarter down from the north edge), and a dot at (10, 10).
    let marks = [
        Mark { role: Role::Curve, points: vec![DVec2::new(20.0, 75.0), DVec2::new(80.0, 75.0)], closed: false },
        Mark { role: Role::Depression, points: vec![DVec2::new(10.0, 10.0)], closed: false },
    ];
    draw_marks(&mut image, &marks, &extent);
    assert_eq!(pixel(&image, 50, 25), [230, 20, 20], "the line's colour on its row");
    assert_eq!(pixel(&image, 50, 27), [20, 20, 20], "a dark halo beside it");
    assert_eq!(pixel(&image, 50, 30), [128; 3], "nothing further off");
    assert_eq!(pixel(&image, 10, 25), [128; 3], "nothing beyond its end");
    assert_eq!(pixel(&image, 10, 90), [40, 120, 255], "the dot, north up");
    assert_eq!(pixel(&image, 10, 10), [128; 3]);
}

#[test]
fn marks_off_the_image_or_not_finite_are_clipped_without_panicking() {
    let extent = Extent::new(DVec2::ZERO, DVec2::splat(100.0));
    let mut image = grey(32);
    let far = [
        Mark { role: Role::Stroke, points: vec![DVec2::new(-1e300, 5.0), DVec2::new(-1e299, 5.0)], closed: true },
        Mark { role: Role::Stroke, points: vec![DVec2::new(1e300, -1e300), DVec2::splat(1e300)], closed: false },
        Mark { role: Role::Stroke, points: vec![DVec2::splat(f64::NAN), DVec2::ZERO], closed: false },
        Mark { role: Role::Peak, points: vec![DVec2::new(1e9, 5.0)], closed: false },
        Mark { role: Role::Peak, points: Vec::new(), closed: true },
    ];
    draw_marks(&mut image, &far, &extent);
    assert!(image.pixels.iter().all(|&v| v == 128));
    // Clipping keeps exactly the part inside: a line from far south-west to the centre colours
    // the diagonal up to the centre and no further; a vertical line west of the image draws
    // nothing, one through it a whole column.
    let mut clipped = grey(101);
    let marks = [
        Mark { role: Role::Curve, points: vec![DVec2::splat(-1e9), DVec2::splat(50.0)], closed: false },
        Mark { role: Role::Stroke, points: vec![DVec2::new(-20.0, -1e9), DVec2::new(-20.0, 1e9)], closed: false },
        Mark { role: Role::Hill, points: vec![DVec2::new(75.0, 1e9), DVec2::new(75.0, -1e9)], closed: false },
    ];
    draw_marks(&mut clipped, &marks, &extent);
    assert_eq!(pixel(&clipped, 0, 100), [230, 20, 20], "the south-west corner");
    assert_eq!(pixel(&clipped, 50, 50), [230, 20, 20], "the centre");
    assert_eq!(pixel(&clipped, 30, 70), [230, 20, 20], "on the way");
    assert_eq!(pixel(&clipped, 70, 30), [128; 3], "past the centre");
    assert!((0..101).all(|y| pixel(&clipped, 75, y) == [255, 230, 0]), "the whole column");
    assert!((0..101).all(|y| pixel(&clipped, 0, y) != [255, 0, 200]), "nothing of the line off the west edge");
    // A line from far away that crosses the image is drawn where it crosses.
    let across =
        [Mark { role: Role::Stroke, points: vec![DVec2::new(-1e12, 50.0), DVec2::new(1e12, 50.0)], closed: false }];
    draw_marks(&mut image, &across, &extent);
    assert!((0..32).all(|x| pixel(&image, x, 16) == [255, 0, 200]));
    let mut tiny = RgbImage { width: 1, height: 1, pixels: vec![0; 3] };
    draw_marks(&mut tiny, &far, &extent);
}
