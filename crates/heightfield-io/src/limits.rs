//! Resource limits applied to every header before anything is allocated.

use crate::IoErrorKind;

/// Caps on what a file may make a reader allocate, checked against the header before decoding.
///
/// As in image-rs, a header is untrusted: every reader computes `nx · ny` with checked arithmetic,
/// compares it with [`Limits::max_cells`], and where the format allows (raw, `.hgt`, uncompressed
/// TIFF/EXR, text grids) also checks that the file is long enough to hold that many samples before
/// it allocates the sample buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub struct Limits {
    /// Largest number of cells (`nx · ny`) a reader accepts. Default 2^30 (a 32768² grid, 4 GiB of
    /// f32 samples).
    pub max_cells: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Self { max_cells: 1 << 30 }
    }
}

impl Limits {
    /// The same limits with at most `max_cells` cells.
    #[must_use]
    pub fn with_max_cells(mut self, max_cells: u64) -> Self {
        self.max_cells = max_cells;
        self
    }

    /// `nx · ny` if it is within the limit (and the address space).
    pub(crate) fn check(self, nx: u64, ny: u64) -> Result<usize, IoErrorKind> {
        let cells = nx.saturating_mul(ny);
        if cells > self.max_cells {
            return Err(IoErrorKind::TooLarge { cells, limit: self.max_cells });
        }
        usize::try_from(cells).map_err(|_| IoErrorKind::TooLarge { cells, limit: usize::MAX as u64 })
    }

    /// The cell limit as a byte budget for a dependency's own limits: `bytes_per_cell` per cell plus
    /// `slack` for headers and row buffers.
    pub(crate) fn byte_budget(self, bytes_per_cell: u64, slack: u64) -> usize {
        let b = self.max_cells.saturating_mul(bytes_per_cell).saturating_add(slack);
        usize::try_from(b).unwrap_or(usize::MAX)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cell_counts_saturate_instead_of_overflowing() {
        let l = Limits::default();
        assert_eq!(l.check(32_768, 32_768).unwrap(), 1 << 30);
        assert!(matches!(l.check(32_768, 32_769), Err(IoErrorKind::TooLarge { .. })));
        assert!(matches!(
            l.with_max_cells(u64::MAX - 1).check(u64::MAX, u64::MAX),
            Err(IoErrorKind::TooLarge { cells: u64::MAX, .. })
        ));
        assert_eq!(Limits::default().with_max_cells(10).byte_budget(4, 1), 41);
    }
}
