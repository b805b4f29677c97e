//! The union–find lookup the floods share: the basin flood of the analysis (over ascent basins),
//! prominence on a divide tree (over peaks) and the ridge spanning tree of synthesis (Kruskal over
//! peaks). Its own module so that none of those modules depends on another for it.

/// Union–find root of `x` with path halving; `parent[r] == r` marks a root.
pub(crate) fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let up = parent[parent[x as usize] as usize];
        parent[x as usize] = up;
        x = up;
    }
    x
}
