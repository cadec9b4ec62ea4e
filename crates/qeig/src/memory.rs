//! How much memory the Krylov basis may take, and the error when it would not fit.
//!
//! The basis is the largest allocation of a run (`vectors × n` scalars: at a million
//! quaternion unknowns and 180 vectors, 5.8 GB), so it is reserved once, before the iteration
//! starts, and a request that cannot fit is refused then with the size it needs, instead of the
//! process being killed by the operating system half-way through.

use thiserror::Error;

/// The Krylov basis of a run would not fit in the memory available.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[error(
    "the Lanczos basis needs {} ({vectors} vectors of {dimension} entries of {bytes_per_entry} bytes){}; \
     ask for fewer pairs, or run where more memory is available",
    gibibytes(self.bytes_needed()),
    match bytes_available {
        Some(available) => format!(" but only {} are available", gibibytes(*available)),
        None => " and could not be allocated".to_string(),
    }
)]
pub struct BasisTooLarge {
    /// Columns of the basis (constraints, locked pairs, active basis and continuation).
    pub vectors: usize,
    /// Length of each vector (the iteration-space dimension).
    pub dimension: usize,
    /// Bytes per entry (8 for `f64`, 16 for complex, 32 for quaternions).
    pub bytes_per_entry: usize,
    /// The limit it was checked against: the option's, else the memory available to the
    /// process (`None` if that is unknown and the allocation itself failed).
    pub bytes_available: Option<u64>,
}

impl BasisTooLarge {
    /// Bytes the basis needs.
    pub fn bytes_needed(&self) -> u64 {
        (self.vectors as u64)
            .saturating_mul(self.dimension as u64)
            .saturating_mul(self.bytes_per_entry as u64)
    }
}

fn gibibytes(bytes: u64) -> String {
    format!("{:.2} GiB", bytes as f64 / f64::from(1u32 << 30))
}

/// Memory the process can still allocate without swapping, where the system says: the
/// smaller of the kernel's estimate `MemAvailable` (`/proc/meminfo`) and the room left under
/// the control group's limit (`memory.max − memory.current`, cgroup v2). `None` elsewhere.
pub(crate) fn available_bytes() -> Option<u64> {
    let meminfo = std::fs::read_to_string("/proc/meminfo").ok();
    let available = meminfo.as_deref().and_then(|text| {
        let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
        let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
        Some(kib.saturating_mul(1024))
    });
    let read = |file: &str| -> Option<u64> {
        std::fs::read_to_string(format!("/sys/fs/cgroup/{file}"))
            .ok()?
            .trim()
            .parse()
            .ok()
    };
    let cgroup_room = read("memory.max")
        .zip(read("memory.current"))
        .map(|(max, current)| max.saturating_sub(current));
    match (available, cgroup_room) {
        (Some(a), Some(c)) => Some(a.min(c)),
        (a, c) => a.or(c),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn message_names_the_size_and_what_to_do() {
        let error = BasisTooLarge {
            vectors: 180,
            dimension: 1_000_000,
            bytes_per_entry: 32,
            bytes_available: Some(4 << 30),
        };
        assert_eq!(error.bytes_needed(), 5_760_000_000);
        let message = error.to_string();
        assert!(message.contains("5.36 GiB"), "{message}");
        assert!(
            message.contains("180 vectors of 1000000 entries"),
            "{message}"
        );
        assert!(message.contains("only 4.00 GiB are available"), "{message}");
        assert!(message.contains("fewer pairs"), "{message}");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn available_memory_is_known_on_linux() {
        let bytes = available_bytes().expect("/proc/meminfo is readable");
        assert!(bytes > 1 << 20, "{bytes} bytes");
    }
}
