//! The allocator hands big freed blocks back to the system (`heap.rs`).

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

/// Without the setting, glibc serves a block from its heap once a bigger
/// one was freed, and keeps it resident when it is freed in turn.
#[cfg(all(target_os = "linux", target_env = "gnu"))]
#[test]
fn a_freed_big_block_leaves_nothing_resident() {
    const MIB: usize = 1 << 20;
    kessler::heap::hand_back_big_blocks();
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
