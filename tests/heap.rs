//! The allocator hands big freed blocks back to the system and shares one
//! heap among all threads (`src/memory/heap.rs`). Its settings hold for the whole
//! process, so these checks run one after another in `main` (no test
//! harness, no threads of its own), after the settings, as in the binary.

/// Resident memory of this process, in bytes (Linux's `VmRSS`).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn resident() -> usize {
    let status = std::fs::read_to_string("/proc/self/status").expect("/proc/self/status is readable");
    let line = status
        .lines()
        .find(|l| l.starts_with("VmRSS:"))
        .expect("VmRSS is listed");
    let kib: usize = line
        .trim_start_matches("VmRSS:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .expect("VmRSS is a number of kB");
    kib * 1024
}

#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MIB: usize = 1 << 20;

/// Without the setting, glibc serves a block from its heap once a bigger
/// one was freed, and keeps it resident when it is freed in turn.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn a_freed_big_block_leaves_nothing_resident() {
    drop(std::hint::black_box(vec![1u8; 30 * MIB]));
    let before = resident();
    let block = std::hint::black_box(vec![1u8; 24 * MIB]);
    let with = resident();
    drop(block);
    let after = resident();
    assert!(
        with >= before + 20 * MIB,
        "the block was not resident: {before} → {with} bytes"
    );
    assert!(
        after + 20 * MIB <= with,
        "the freed block stayed resident: {with} → {after} bytes"
    );
}

/// Small blocks (below `BIG_BLOCK`) that one worker frees serve another
/// worker's: with a heap per thread (glibc's default), the second worker's
/// blocks would be resident beside the first's freed ones.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn what_one_worker_frees_serves_another() {
    use std::sync::Barrier;
    const BLOCK: usize = 64 << 10;
    const BLOCKS: usize = 24 * MIB / BLOCK;
    let blocks = || -> Vec<Vec<u8>> { (0..BLOCKS).map(|_| std::hint::black_box(vec![1u8; BLOCK])).collect() };
    // Both workers alive throughout, as a pool's are; the second allocates
    // only once the first has freed.
    let (freed, allocated, done) = (Barrier::new(3), Barrier::new(3), Barrier::new(3));
    let (before, after) = std::thread::scope(|scope| {
        scope.spawn(|| {
            drop(blocks());
            freed.wait();
            allocated.wait();
            done.wait();
        });
        scope.spawn(|| {
            freed.wait();
            let kept = blocks();
            allocated.wait();
            done.wait();
            drop(kept);
        });
        freed.wait();
        let before = resident();
        allocated.wait();
        let after = resident();
        done.wait();
        (before, after)
    });
    assert!(
        after < before + 12 * MIB,
        "the second worker's 24 MiB did not reuse the first's: {before} → {after} bytes"
    );
}

fn main() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        kessler::memory::hand_back_big_blocks();
        a_freed_big_block_leaves_nothing_resident();
        println!("a freed big block leaves nothing resident: ok");
        what_one_worker_frees_serves_another();
        println!("what one worker frees serves another: ok");
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    println!("heap tests skipped: the settings are glibc's, and this is not Linux with glibc");
}
