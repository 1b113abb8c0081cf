//! The program's allocator, and the heap it holds: counted so the server can refuse and stop work
//! before its memory runs out, rather than abort when an allocation fails (which a Rust program on
//! stable cannot turn into an error).

use cap::Cap;

/// mimalloc rather than the system allocator. A design run keeps a few thousand candidate travels (tens
/// of megabytes) alive at once; glibc's per-thread heaps grow in small steps, each page faulted and
/// zeroed on its own, while mimalloc commits its arena in large pages. The folding table's whole run
/// faults about 300 pages with it, 8,900 with glibc's (`perf stat -e page-faults linkwright design
/// SCENE -o /tmp/out --no-print-check --threads 2`), and the Table-1 scenes' whole runs are 3–13%
/// shorter (`hyperfine -N --warmup 3 --runs 20` on that command, docs/performance.md); the designs
/// are the same. No limit is set on the count: past one, an allocation would fail and abort the
/// process.
#[global_allocator]
static ALLOCATOR: Cap<mimalloc::MiMalloc> = Cap::new(mimalloc::MiMalloc, usize::MAX);

/// The heap bytes the process holds now (as asked of the allocator, without its own overhead).
pub(crate) fn live_bytes() -> usize {
    ALLOCATOR.allocated()
}

#[cfg(test)]
mod tests {
    use super::live_bytes;

    /// Unit tests run on the program's allocator.
    #[test]
    fn the_count_follows_allocations_and_frees() {
        // Other tests allocate at the same time: a block far larger than their noise is looked for.
        const SIZE: usize = 256 << 20;
        const NOISE: usize = 32 << 20;
        let before = live_bytes();
        let block = std::hint::black_box(vec![7u8; SIZE]);
        let during = live_bytes();
        drop(block);
        let after = live_bytes();
        assert!(during + NOISE >= before + SIZE, "{before} -> {during}");
        assert!(after + SIZE <= during + NOISE, "{during} -> {after}");
    }
}
