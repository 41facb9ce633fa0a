//! How much memory this process may use, and so how many bodies a run may
//! grow to before an allocation would fail: the smallest of the
//! address-space limit (`ulimit -v`), the control group's memory limit
//! (cgroup v2 `memory.max`, v1 `memory.limit_in_bytes`) and the machine's
//! memory. Read from Linux's `/proc` and `/sys`; elsewhere, or where they
//! cannot be read, there is no limit and the run is held only to its
//! `max_bodies`.

use std::fmt;

/// Memory one body may take at a run's peak, in bytes: the ECS's
/// components and entity (about 180 bytes), the broad phase's filing
/// (about 32), and room for a table that doubles as it grows (measured:
/// 224–242 bytes a body of peak resident memory while shattering grew a
/// cloud to 1 and 4 million bodies; address space runs higher).
pub const BYTES_PER_BODY: u64 = 500;

/// Which limit binds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitKind {
    /// The address-space limit (`ulimit -v`, `RLIMIT_AS`).
    AddressSpace,
    /// The control group's memory limit.
    ControlGroup,
    /// The machine's memory (`MemTotal`).
    Machine,
}

impl fmt::Display for LimitKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::AddressSpace => "the address-space limit (ulimit -v)",
            Self::ControlGroup => "the control group's memory limit",
            Self::Machine => "this machine's memory",
        })
    }
}

/// The memory a run may still take, and the limit that says so.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryLimit {
    /// Bytes the process may still take beyond what it holds now.
    pub free_bytes: u64,
    /// The limit, in bytes.
    pub limit_bytes: u64,
    /// Which limit it is.
    pub kind: LimitKind,
}

impl MemoryLimit {
    /// The limit that binds this process now, if any is known.
    pub fn of_this_process() -> Option<Self> {
        let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
        let size = status_kib(&status, "VmSize:").map_or(0, |k| k * 1024);
        let resident = status_kib(&status, "VmRSS:").map_or(0, |k| k * 1024);
        let read = |path: &str| std::fs::read_to_string(path).ok();
        let address_space = read("/proc/self/limits")
            .and_then(|t| address_space_limit(&t))
            .map(|limit| (limit, LimitKind::AddressSpace, size));
        let group = cgroup_limit(&read("/proc/self/cgroup").unwrap_or_default(), read)
            .map(|limit| (limit, LimitKind::ControlGroup, resident));
        let machine = read("/proc/meminfo")
            .and_then(|t| status_kib(&t, "MemTotal:"))
            .map(|kib| (kib * 1024, LimitKind::Machine, resident));
        [address_space, group, machine]
            .into_iter()
            .flatten()
            .map(|(limit_bytes, kind, used)| Self {
                free_bytes: limit_bytes.saturating_sub(used),
                limit_bytes,
                kind,
            })
            .min_by_key(|l| l.free_bytes)
    }

    /// The most bodies a run may hold within this limit.
    pub fn bodies(&self) -> u64 {
        self.free_bytes / BYTES_PER_BODY
    }
}

/// A `Name:   1234 kB` line's number, in KiB.
fn status_kib(text: &str, name: &str) -> Option<u64> {
    let line = text.lines().find(|l| l.starts_with(name))?;
    line[name.len()..].trim().strip_suffix("kB")?.trim().parse().ok()
}

/// The soft limit of `Max address space` in `/proc/self/limits`, in bytes;
/// `None` if unlimited.
fn address_space_limit(limits: &str) -> Option<u64> {
    let line = limits.lines().find(|l| l.starts_with("Max address space"))?;
    line["Max address space".len()..]
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

/// The memory limit of this process's control group, from `/proc/self/cgroup`
/// and the files `read` reads; `None` if there is none (or it is "max", or
/// beyond any machine).
fn cgroup_limit(cgroup: &str, read: impl Fn(&str) -> Option<String>) -> Option<u64> {
    let mut candidates = Vec::new();
    for line in cgroup.lines() {
        let mut parts = line.splitn(3, ':');
        let (_, controllers, path) = (parts.next()?, parts.next()?, parts.next()?);
        if controllers.is_empty() {
            candidates.push(format!("/sys/fs/cgroup{path}/memory.max"));
            candidates.push("/sys/fs/cgroup/memory.max".to_owned());
        } else if controllers.split(',').any(|c| c == "memory") {
            candidates.push(format!("/sys/fs/cgroup/memory{path}/memory.limit_in_bytes"));
            candidates.push("/sys/fs/cgroup/memory/memory.limit_in_bytes".to_owned());
        }
    }
    let limit = candidates.iter().find_map(|path| read(path))?;
    // "max" (v2) or a page-rounded i64::MAX (v1) mean none.
    limit.trim().parse::<u64>().ok().filter(|&bytes| bytes < 1 << 60)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_are_read_from_procs_words() {
        let limits = "Limit                     Soft Limit           Hard Limit           Units\n\
                      Max address space         6000000000           unlimited            bytes\n";
        assert_eq!(address_space_limit(limits), Some(6_000_000_000));
        let unlimited = "Max address space         unlimited            unlimited            bytes\n";
        assert_eq!(address_space_limit(unlimited), None);
        assert_eq!(status_kib("VmSize:\t  3892 kB\nVmRSS:\t 100 kB\n", "VmRSS:"), Some(100));
    }

    #[test]
    fn a_control_groups_limit_is_found_in_v2_and_v1() {
        let files = |path: &str| match path {
            "/sys/fs/cgroup/user.slice/memory.max" => Some("2147483648\n".to_owned()),
            "/sys/fs/cgroup/memory/memory.limit_in_bytes" => Some("9223372036854771712\n".to_owned()),
            "/sys/fs/cgroup/memory/job/memory.limit_in_bytes" => Some("1073741824\n".to_owned()),
            _ => None,
        };
        assert_eq!(cgroup_limit("0::/user.slice\n", files), Some(2 << 30));
        assert_eq!(cgroup_limit("4:memory:/job\n", files), Some(1 << 30));
        assert_eq!(cgroup_limit("4:memory:/elsewhere\n", files), None, "v1 unlimited");
        assert_eq!(cgroup_limit("0::/x\n", |_| Some("max\n".to_owned())), None);
    }

    #[test]
    fn a_limit_holds_its_bytes_over_the_bytes_per_body() {
        let limit = MemoryLimit {
            free_bytes: 5_000,
            limit_bytes: 6_000,
            kind: LimitKind::Machine,
        };
        assert_eq!(limit.bodies(), 10);
    }
}
