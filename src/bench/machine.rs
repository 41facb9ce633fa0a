//! What machine a benchmark ran on: written beside its results as
//! `<stem>-machine.txt`, so that figures never travel without it.

use std::fmt::Write as _;

use crate::Simulation;
use crate::execution::{Execution, ExecutionMode, available_threads};
use crate::scenario::Scenario;
use crate::systems::Kernel;

/// The reference run whose state hash the report gives: a collapse under
/// tree gravity that shatters, so that two machines whose hashes agree
/// compute the gravity kernels, the shatters and the maths alike.
const REFERENCE: &str = include_str!("../../scenarios/collapse.ron");

/// Updates of the reference run.
const REFERENCE_UPDATES: u64 = 50;

/// The state hash of the reference run, and what it is.
pub fn reference_hash() -> String {
    let scenario =
        Scenario::parse(REFERENCE, "scenarios/collapse.ron (built in)").expect("a shipped scenario (tested)");
    let execution = Execution::new(ExecutionMode::Sequential, 1).expect("one thread");
    match Simulation::from_scenario(&scenario, execution) {
        Ok(mut sim) => {
            sim.step(REFERENCE_UPDATES);
            format!(
                "{} (scenarios/collapse.ron, {REFERENCE_UPDATES} updates; equal hashes: this machine computes as that one)",
                sim.state_hash()
            )
        }
        Err(e) => format!("unknown ({e})"),
    }
}

/// A `key: value` line per fact: CPU model, cores and threads, memory, OS,
/// rustc, Kessler's version and commit, the gravity kernel the processor
/// runs, the reference run's state hash, the date (UTC), and the command.
pub fn machine_report(command: &str) -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let mut out = String::new();
    let mut line = |key: &str, value: String| {
        let _ = writeln!(out, "{key}: {value}");
    };
    line(
        "cpu",
        cpu_model(&cpuinfo).unwrap_or_else(|| std::env::consts::ARCH.to_owned()),
    );
    line(
        "cores",
        physical_cores(&cpuinfo).map_or("unknown".into(), |n| n.to_string()),
    );
    line("hardware threads", available_threads().to_string());
    line("memory", memory_total().unwrap_or_else(|| "unknown".into()));
    line("os", os_name());
    line("rustc", env!("KESSLER_RUSTC_VERSION").to_owned());
    line(
        "kessler",
        format!("{} (commit {})", env!("CARGO_PKG_VERSION"), env!("KESSLER_GIT_COMMIT")),
    );
    line("gravity kernel", Kernel::best().name().to_owned());
    line("reference state hash", reference_hash());
    line(
        "profile",
        if cfg!(debug_assertions) { "debug" } else { "release" }.to_owned(),
    );
    line("date", utc_now());
    line("command", command.to_owned());
    out
}

/// The plot's footer: the machine and the build the figures come from.
pub fn plot_footer() -> String {
    format!(
        "{}, {} hardware threads · Kessler {}, commit {} · {}",
        this_cpu(),
        available_threads(),
        env!("CARGO_PKG_VERSION"),
        env!("KESSLER_GIT_COMMIT"),
        utc_now()
    )
}

/// This machine's CPU model (its architecture if unknown).
pub fn this_cpu() -> String {
    cpu_of(&std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default())
}

fn cpu_of(cpuinfo: &str) -> String {
    cpu_model(cpuinfo).unwrap_or_else(|| std::env::consts::ARCH.to_owned())
}

/// `model name` of the first processor in `/proc/cpuinfo`.
fn cpu_model(cpuinfo: &str) -> Option<String> {
    cpuinfo
        .lines()
        .find(|l| l.starts_with("model name"))
        .and_then(|l| l.split_once(':'))
        .map(|(_, v)| v.trim().to_owned())
}

/// Distinct `(physical id, core id)` pairs in `/proc/cpuinfo`.
fn physical_cores(cpuinfo: &str) -> Option<usize> {
    let mut cores = std::collections::BTreeSet::new();
    let (mut package, mut core) = (None, None);
    for l in cpuinfo.lines().chain(std::iter::once("")) {
        let value = || l.split_once(':').map(|(_, v)| v.trim().to_owned());
        if l.starts_with("physical id") {
            package = value();
        } else if l.starts_with("core id") {
            core = value();
        } else if l.trim().is_empty()
            && let Some(c) = core.take()
        {
            cores.insert((package.take(), c));
        }
    }
    (!cores.is_empty()).then_some(cores.len())
}

fn memory_total() -> Option<String> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib: u64 = meminfo
        .lines()
        .find(|l| l.starts_with("MemTotal:"))?
        .split_whitespace()
        .nth(1)?
        .parse()
        .ok()?;
    Some(format!("{:.1} GiB", kib as f64 / f64::from(1 << 20)))
}

fn os_name() -> String {
    let release = std::fs::read_to_string("/etc/os-release").unwrap_or_default();
    let pretty = release
        .lines()
        .find_map(|l| l.strip_prefix("PRETTY_NAME="))
        .map(|v| v.trim_matches('"').to_owned());
    let kernel = std::fs::read_to_string("/proc/sys/kernel/osrelease").ok();
    match (pretty, kernel) {
        (Some(os), Some(k)) => format!("{os}, kernel {}", k.trim()),
        (Some(os), None) => os,
        (None, _) => std::env::consts::OS.to_owned(),
    }
}

/// Now as `YYYY-MM-DD HH:MM:SS UTC`.
pub fn utc_now() -> String {
    utc(time::OffsetDateTime::now_utc())
}

/// `at` as `YYYY-MM-DD HH:MM:SS UTC`.
fn utc(at: time::OffsetDateTime) -> String {
    let at = at.to_offset(time::UtcOffset::UTC);
    format!(
        "{:04}-{:02}-{:02} {:02}:{:02}:{:02} UTC",
        at.year(),
        u8::from(at.month()),
        at.day(),
        at.hour(),
        at.minute(),
        at.second()
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_from_day_counts() {
        let day = |days: i64| utc(time::OffsetDateTime::from_unix_timestamp(days * 86_400).unwrap());
        assert_eq!(day(0), "1970-01-01 00:00:00 UTC");
        assert_eq!(day(11_016), "2000-02-29 00:00:00 UTC");
        assert_eq!(day(20_787), "2026-11-30 00:00:00 UTC");
        let at = time::OffsetDateTime::from_unix_timestamp(20_787 * 86_400 + 3_723).unwrap();
        assert_eq!(utc(at), "2026-11-30 01:02:03 UTC");
    }

    #[test]
    fn cores_are_counted_once_per_physical_core() {
        let cpuinfo = "processor: 0\nphysical id: 0\ncore id: 0\n\nprocessor: 1\nphysical id: 0\ncore id: 0\n\n\
                       processor: 2\nphysical id: 0\ncore id: 1\n";
        assert_eq!(physical_cores(cpuinfo), Some(2));
        assert_eq!(
            cpu_model("model name\t: Some CPU @ 2GHz\n").as_deref(),
            Some("Some CPU @ 2GHz")
        );
    }

    #[test]
    fn the_report_names_the_machine_and_the_build() {
        let report = machine_report("kessler bench x.ron");
        for key in [
            "cpu:",
            "hardware threads:",
            "os:",
            "rustc:",
            "kessler:",
            "reference state hash:",
            "date:",
            "command: kessler bench x.ron",
        ] {
            assert!(report.contains(key), "{key} missing in\n{report}");
        }
    }
}
