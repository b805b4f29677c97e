//! Reference figures our benchmarks are compared with: measured by the issues on this machine
//! class, or reported by the papers (on their hardware, stated with each figure).

/// What a benchmark is compared against.
pub(crate) enum Reference {
    /// A published or previously measured time.
    Fixed {
        /// Who measured it, on what.
        label: &'static str,
        /// Seconds.
        seconds: f64,
    },
    /// Another benchmark of the same run (a foreign implementation measured side by side).
    SideBySide {
        /// What the other benchmark is.
        label: &'static str,
        /// Its criterion id.
        bench: &'static str,
    },
}

/// `(criterion id, reference)`; a benchmark may have several references.
pub(crate) const REFERENCES: &[(&str, Reference)] = &[
    (
        "poisson/rect/100000",
        Reference::Fixed { label: "plain grid Bridson, same machine class (issue #2)", seconds: 0.37 },
    ),
    (
        "poisson/rect/100000",
        Reference::Fixed { label: "`fast_poisson` crate, same machine class (issue #2)", seconds: 1.6 },
    ),
    (
        "poisson/rect/1000000",
        Reference::Fixed { label: "plain grid Bridson, same machine class (issue #2)", seconds: 4.0 },
    ),
    (
        "poisson/rect/1000000",
        Reference::Fixed { label: "`fast_poisson` crate, same machine class (issue #2)", seconds: 65.0 },
    ),
    (
        "tin/build/10000",
        Reference::SideBySide {
            label: "spade `bulk_load` alone, same run (target < 1.3×)",
            bench: "tin/spade_bulk_load/10000",
        },
    ),
    (
        "tin/build/100000",
        Reference::SideBySide {
            label: "spade `bulk_load` alone, same run (target < 1.3×)",
            bench: "tin/spade_bulk_load/100000",
        },
    ),
    (
        "tin/build/1000000",
        Reference::SideBySide {
            label: "spade `bulk_load` alone, same run (target < 1.3×)",
            bench: "tin/spade_bulk_load/1000000",
        },
    ),
    (
        "tin/spade_bulk_load/100000",
        Reference::Fixed { label: "spade `bulk_load`, issue #2's measurement", seconds: 0.090 },
    ),
    (
        "tin/spade_bulk_load/1000000",
        Reference::Fixed { label: "spade `bulk_load`, issue #2's measurement", seconds: 0.7 },
    ),
    (
        "tin/rasterize_100k_to_2048",
        Reference::SideBySide { label: "our serial rasterizer, same run", bench: "tin/rasterize_serial_100k_to_2048" },
    ),
];
