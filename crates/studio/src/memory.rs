//! The memory the running generations are estimated to take, held against one pool: the budget's
//! [`relief::Budget::max_bytes`]. Each scene is checked against it alone before it runs; the
//! pool makes sure that several running at once (up to [`crate::Config::max_jobs`]) cannot add up
//! past it either. A request waits for its share up to [`crate::Config::memory_wait`] (the work
//! a newer edit superseded frees its share as it stops), then gets 503.

use std::sync::Arc;
use std::time::Duration;

use axum::http::StatusCode;
use tokio::sync::{OwnedSemaphorePermit, Semaphore};

use crate::error::ApiError;

/// The pool counts whole MiB (a semaphore's permits are `u32`: up to 4 PiB).
const UNIT: u64 = 1 << 20;

/// The pool and how long a request waits for its share.
#[derive(Debug)]
pub(crate) struct Memory {
    permits: Arc<Semaphore>,
    units: u32,
    wait: Duration,
}

/// A share of the pool, given back when it drops (when the blocking thread holding it ends).
pub(crate) type Held = OwnedSemaphorePermit;

impl Memory {
    /// A pool of `bytes` (rounded down to whole MiB, at least one; unbounded budgets get 4 PiB).
    pub(crate) fn new(bytes: u64, wait: Duration) -> Self {
        let most = u64::from(u32::MAX).min(Semaphore::MAX_PERMITS as u64);
        let units = u32::try_from((bytes / UNIT).clamp(1, most)).unwrap_or(u32::MAX);
        Self { permits: Arc::new(Semaphore::new(units as usize)), units, wait }
    }

    /// Waits for `bytes` of the pool for `what` (a share larger than the pool takes all of it: the
    /// budget's own check refuses those before they get here).
    ///
    /// # Errors
    /// 503 when the share is not free within the wait.
    pub(crate) async fn hold(&self, bytes: u64, what: &str) -> Result<Held, ApiError> {
        let units = u32::try_from(bytes.div_ceil(UNIT)).unwrap_or(u32::MAX).min(self.units);
        let acquire = Arc::clone(&self.permits).acquire_many_owned(units);
        if let Ok(held) = tokio::time::timeout(self.wait, acquire).await {
            return held.map_err(ApiError::internal);
        }
        let busy = self.units.saturating_sub(u32::try_from(self.permits.available_permits()).unwrap_or(0));
        let message = format!(
            "{what} needs about {units} MiB of memory and the running work holds {busy} MiB of the studio's {} MiB \
             (its budget's max_bytes): try again when it ends",
            self.units
        );
        Err(ApiError::new(StatusCode::SERVICE_UNAVAILABLE, message))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[tokio::test]
    async fn shares_add_up_to_the_pool_and_come_back_when_dropped() {
        let memory = Memory::new(10 * UNIT, Duration::from_millis(20));
        let first = memory.hold(6 * UNIT, "a").await.unwrap();
        let refused = memory.hold(5 * UNIT, "b").await.unwrap_err();
        assert_eq!(refused.status(), StatusCode::SERVICE_UNAVAILABLE);
        assert!(refused.message().contains("about 5 MiB") && refused.message().contains("holds 6 MiB"), "{refused:?}");
        // What fits beside it, and what waits for it to end.
        let second = memory.hold(4 * UNIT, "c").await.unwrap();
        drop(first);
        let third = memory.hold(5 * UNIT + 1, "d").await.unwrap();
        assert_eq!(memory.permits.available_permits(), 0);
        drop((second, third));
        // A share larger than the pool takes all of it rather than waiting forever.
        assert!(memory.hold(100 * UNIT, "e").await.is_ok());
        assert_eq!(Memory::new(u64::MAX, Duration::ZERO).units, u32::MAX);
    }
}
