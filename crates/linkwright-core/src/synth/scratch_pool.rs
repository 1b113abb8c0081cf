//! Scratch buffers handed from one parallel task to the next.
//!
//! Rayon's `map_init` makes a new value for every piece of work it splits off, many per chunk on two
//! threads, and a new scratch grows its buffers and compiles its plan again. A pool keeps the
//! scratches of the tasks that ended for the tasks that start. What a scratch holds never changes a
//! result (a worker already reuses one across the items of its piece, whichever they are), so
//! neither does which scratch a task gets.

use std::ops::{Deref, DerefMut};
use std::sync::{Mutex, PoisonError};

/// Scratches not in use.
pub(crate) struct ScratchPool<T> {
    spare: Mutex<Vec<T>>,
}

impl<T> Default for ScratchPool<T> {
    fn default() -> Self {
        ScratchPool { spare: Mutex::new(Vec::new()) }
    }
}

impl<T> std::fmt::Debug for ScratchPool<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ScratchPool").finish_non_exhaustive()
    }
}

impl<T: Default> ScratchPool<T> {
    /// A scratch of the pool (a new one when all are in use), back in the pool when dropped.
    pub(crate) fn take(&self) -> Pooled<'_, T> {
        // The lock is held only to push or pop, which cannot panic: a poisoned lock still holds a
        // consistent list.
        let item = self.spare.lock().unwrap_or_else(PoisonError::into_inner).pop().unwrap_or_default();
        Pooled { pool: self, item }
    }
}

/// A scratch taken from a [`ScratchPool`].
pub(crate) struct Pooled<'a, T: Default> {
    pool: &'a ScratchPool<T>,
    item: T,
}

impl<T: Default> Deref for Pooled<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.item
    }
}

impl<T: Default> DerefMut for Pooled<'_, T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.item
    }
}

impl<T: Default> Drop for Pooled<'_, T> {
    fn drop(&mut self) {
        let item = std::mem::take(&mut self.item);
        self.pool.spare.lock().unwrap_or_else(PoisonError::into_inner).push(item);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scratch returned to the pool is the next one taken, buffers and all; a scratch taken while
    /// another is out is a new one.
    #[test]
    fn returned_scratches_are_taken_again() {
        let pool: ScratchPool<Vec<u32>> = ScratchPool::default();
        {
            let mut a = pool.take();
            a.extend([1, 2, 3]);
            let b = pool.take();
            assert!(b.is_empty());
        }
        let (c, d) = (pool.take(), pool.take());
        let mut taken = [c.clone(), d.clone()];
        taken.sort();
        assert_eq!(taken, [vec![], vec![1, 2, 3]]);
    }
}
