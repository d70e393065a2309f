//! The WGSL kernels, each a source made of the files it is written in: a kernel that walks the
//! hierarchy is `walk.wgsl` and `morton.wgsl` followed by its own file. `tests/translations.rs` translates each
//! entry point for engines not on wgpu.

/// One WGSL module and its entry points.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Kernel {
    /// Its name (the file that holds its entry points, without `.wgsl`).
    pub name: &'static str,
    source: &'static str,
    /// Its entry points, each a compute kernel.
    pub entries: &'static [&'static str],
}

impl Kernel {
    /// The module's whole WGSL source.
    #[must_use]
    pub fn source(&self) -> &'static str {
        self.source
    }
}

/// Eq. (1)'s blended sum at shading points (`walk.wgsl` + `shade.wgsl`).
pub const SHADE: Kernel = Kernel {
    name: "shade",
    source: concat!(
        include_str!("walk.wgsl"),
        include_str!("morton.wgsl"),
        include_str!("shade.wgsl")
    ),
    entries: &["shade"],
};

/// K lights a point drawn by their unshadowed light (`walk.wgsl` + `gather.wgsl`).
pub const GATHER: Kernel = Kernel {
    name: "gather",
    source: concat!(
        include_str!("walk.wgsl"),
        include_str!("morton.wgsl"),
        include_str!("gather.wgsl")
    ),
    entries: &["gather"],
};

/// The prefix sum (`scan.wgsl`).
pub const SCAN: Kernel = Kernel {
    name: "scan",
    source: include_str!("scan.wgsl"),
    entries: &["scan_blocks", "add_sums"],
};

/// The radix sort (`sort.wgsl`).
pub const SORT: Kernel = Kernel {
    name: "sort",
    source: include_str!("sort.wgsl"),
    entries: &["count_digits", "scatter_digits"],
};

/// The build: the lights counted and sorted into level-1 cells and the splat of eqs. (1), (2), (4), (5)
/// (`build.wgsl`).
pub const BUILD: Kernel = Kernel {
    name: "build",
    source: concat!(
        include_str!("step.wgsl"),
        include_str!("build.wgsl"),
        include_str!("morton.wgsl")
    ),
    entries: &[
        "locate",
        "copy_counts",
        "gather_sorted",
        "splat",
        "moment_parts",
        "finish_moments",
        "size_parts",
        "finish_vertices",
        "list_vertices",
    ],
};

/// Each level's vertices marked (`mark.wgsl`).
pub const MARK: Kernel = Kernel {
    name: "mark",
    source: concat!(
        include_str!("step.wgsl"),
        include_str!("mark.wgsl"),
        include_str!("morton.wgsl")
    ),
    entries: &["clear_slots", "mark_corners"],
};

/// Every kernel of the crate.
pub const ALL: [Kernel; 6] = [SHADE, GATHER, SCAN, SORT, BUILD, MARK];
