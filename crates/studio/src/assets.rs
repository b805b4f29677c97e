//! The page, compiled into the binary: no front-end build step, nothing to install.

/// `(route, content type, body)` of every static file.
pub(crate) const FILES: [(&str, &str, &str); 6] = [
    ("/", "text/html; charset=utf-8", include_str!("../web/index.html")),
    ("/studio.js", "text/javascript; charset=utf-8", include_str!("../web/studio.js")),
    ("/bezier.js", "text/javascript; charset=utf-8", include_str!("../web/bezier.js")),
    ("/shapes.js", "text/javascript; charset=utf-8", include_str!("../web/shapes.js")),
    ("/view3d.js", "text/javascript; charset=utf-8", include_str!("../web/view3d.js")),
    ("/studio.css", "text/css; charset=utf-8", include_str!("../web/studio.css")),
];

/// Starter scenes offered by the page's "New" menu: `(name, scene JSON)`.
pub(crate) fn templates() -> Vec<(&'static str, String)> {
    vec![
        ("demo", relief::scene::DEMO_SCENE.to_owned()),
        ("island", include_str!("../web/templates/island.json").to_owned()),
        ("contours", include_str!("../web/templates/contours.json").to_owned()),
        ("curves", include_str!("../web/templates/curves.json").to_owned()),
    ]
}
