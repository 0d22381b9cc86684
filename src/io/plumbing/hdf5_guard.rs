//! A deadline for libhdf5's metadata reads, so that a corrupt HDF5 file can never hang the tool.
//!
//! libhdf5 trusts the bytes of a file's metadata. Some corruptions make it loop forever: a global
//! heap collection whose free-space object (index 0) records a size of 0 makes
//! `H5HG__cache_heap_deserialize` (libhdf5 2.2.0, the newest release) spin without advancing,
//! and every variable-length string attribute of the file (cooler's `format`, `bin-type`,
//! `storage-mode`, ...) is read through that heap. The loop runs inside libhdf5, behind its global
//! lock: no Rust code can interrupt it.
//!
//! So every libhdf5 call that reads a file's metadata (opening the file, attributes, string
//! datasets: small reads that take milliseconds on any healthy file) runs through [`guarded`],
//! which registers a deadline with one watchdog thread. When a call outlives its deadline the
//! watchdog calls the handler installed with [`set_timeout_handler`]: the `contactmap` binary's
//! prints one error line naming the file and what was being read, and exits with status 2 (libhdf5
//! registers no exit handler: hdf5-metno calls `H5dont_atexit`). Library users who install no
//! handler keep libhdf5's behaviour. Bulk reads (pixel and bin columns) are not guarded: their time
//! grows with the file, and contactmap's own chunk reader bounds them.
//!
//! The deadline is [`DEFAULT_TIMEOUT`], or `CONTACTMAP_HDF5_TIMEOUT` seconds when that variable is
//! set (for very slow network file systems).

use std::collections::BTreeMap;
use std::sync::{Condvar, Mutex, OnceLock};
use std::time::{Duration, Instant};

use crate::error::{Error, Result};

/// The deadline of one guarded metadata call when `CONTACTMAP_HDF5_TIMEOUT` is not set.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_secs(5);

/// What the watchdog calls with its message when a guarded call outlives its deadline.
pub type TimeoutHandler = fn(&str);

static HANDLER: OnceLock<TimeoutHandler> = OnceLock::new();

/// Install the function called when a guarded libhdf5 call outlives its deadline (once per
/// process; later calls are ignored). It receives a message naming the file and the read.
pub fn set_timeout_handler(handler: TimeoutHandler) {
    let _ = HANDLER.set(handler);
}

/// The deadline of each guarded call: `CONTACTMAP_HDF5_TIMEOUT` (seconds) or [`DEFAULT_TIMEOUT`].
pub fn timeout() -> Duration {
    static TIMEOUT: OnceLock<Duration> = OnceLock::new();
    *TIMEOUT.get_or_init(|| {
        std::env::var("CONTACTMAP_HDF5_TIMEOUT")
            .ok()
            .and_then(|v| v.trim().parse::<f64>().ok())
            .filter(|s| s.is_finite() && *s > 0.0)
            .map_or(DEFAULT_TIMEOUT, Duration::from_secs_f64)
    })
}

#[derive(Default)]
struct Pending {
    next_id: u64,
    /// Active calls: id -> (deadline, message).
    calls: BTreeMap<u64, (Instant, String)>,
}

struct Watchdog {
    pending: Mutex<Pending>,
    wake: Condvar,
}

fn watchdog() -> &'static Watchdog {
    static WATCHDOG: OnceLock<&'static Watchdog> = OnceLock::new();
    WATCHDOG.get_or_init(|| {
        let dog: &'static Watchdog = Box::leak(Box::new(Watchdog {
            pending: Mutex::new(Pending::default()),
            wake: Condvar::new(),
        }));
        std::thread::Builder::new()
            .name("hdf5-watchdog".into())
            .spawn(move || dog.watch())
            .expect("the HDF5 watchdog thread could not be started");
        dog
    })
}

impl Watchdog {
    fn watch(&self) {
        let mut pending = self.pending.lock().unwrap_or_else(|e| e.into_inner());
        loop {
            let earliest = pending
                .calls
                .iter()
                .min_by_key(|(_, (deadline, _))| *deadline)
                .map(|(&id, (deadline, message))| (id, *deadline, message.clone()));
            match earliest {
                None => {
                    pending = self.wake.wait(pending).unwrap_or_else(|e| e.into_inner());
                }
                Some((id, deadline, message)) => {
                    let now = Instant::now();
                    if now < deadline {
                        pending = self
                            .wake
                            .wait_timeout(pending, deadline - now)
                            .unwrap_or_else(|e| e.into_inner())
                            .0;
                        continue;
                    }
                    pending.calls.remove(&id);
                    drop(pending);
                    if let Some(handler) = HANDLER.get() {
                        handler(&message);
                    }
                    pending = self.pending.lock().unwrap_or_else(|e| e.into_inner());
                }
            }
        }
    }
}

/// Run `call`, a libhdf5 read of `what` in the file `path`, under the metadata deadline
/// ([`timeout`]): if it has not returned by then, the installed handler is called with
/// `"PATH: HDF5 reading WHAT did not finish within N s: ..."`.
pub fn guarded<T>(path: &str, what: &str, call: impl FnOnce() -> T) -> T {
    guarded_for(timeout(), path, what, call)
}

fn guarded_for<T>(limit: Duration, path: &str, what: &str, call: impl FnOnce() -> T) -> T {
    let dog = watchdog();
    let message = format!(
        "{path}: HDF5 reading {what} did not finish within {} s: the file's metadata is corrupt \
         (libhdf5 loops on it); `contactmap validate` checks a file, and \
         CONTACTMAP_HDF5_TIMEOUT=SECONDS allows slower file systems more time",
        limit.as_secs_f64()
    );
    let id = {
        let mut pending = dog.pending.lock().unwrap_or_else(|e| e.into_inner());
        let id = pending.next_id;
        pending.next_id += 1;
        pending.calls.insert(id, (Instant::now() + limit, message));
        id
    };
    dog.wake.notify_one();
    let result = call();
    dog.pending
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .calls
        .remove(&id);
    result
}

/// Text from bytes stored in an HDF5 string, invalid UTF-8 replaced by U+FFFD. hdf5-metno's
/// `as_str` on its string types trusts the bytes (`from_utf8_unchecked`): on a corrupt file that
/// is undefined behaviour (a segfault when the text is formatted), so file strings go through
/// here instead.
pub fn lossy(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Largest ratio of a dataset's size in memory to the bytes it occupies in the file. Deflate
/// (cooler's compression) cannot compress more than about 1032:1 and blosc (as HiCMatrix uses
/// it) about 160:1, so a
/// dataset claiming more values than that is a corrupt dataspace, refused before any allocation.
const MAX_EXPANSION: u64 = 4096;

/// Datasets up to this many bytes in memory are read whatever their storage (compact layouts).
const SMALL_DATASET_BYTES: u64 = 1 << 20;

/// The number of values of `dataset` (`name` in the file `path` of `file_len` bytes), after
/// checking that the file can hold them: a corrupt dataspace must give an error naming the
/// dataset, not an allocation of terabytes.
pub fn checked_len(
    path: &str,
    dataset: &hdf5::Dataset,
    name: &str,
    file_len: u64,
) -> Result<usize> {
    let (n_values, value_bytes, storage, filters) = guarded(path, name, || {
        let value_bytes = dataset.dtype().map_or(1, |t| t.size());
        let filters = dataset.dcpl().and_then(|p| p.get_filters());
        (dataset.size(), value_bytes, dataset.storage_size(), filters)
    });
    // hdf5-metno's blosc filter indexes its parameters without checking their number and
    // dereferences a null name for an unknown compressor code (SIGSEGV on a damaged filter
    // message): its own parser checks them without crashing, so a pipeline it refuses is refused
    // here before any chunk goes through the filter.
    if let Err(e) = filters {
        return Err(Error::format(
            path,
            format!("{name}: unsupported or corrupt filter pipeline ({e})"),
        ));
    }
    let claimed = (n_values as u64).saturating_mul(value_bytes as u64);
    if storage > file_len
        || claimed > SMALL_DATASET_BYTES.saturating_add(MAX_EXPANSION.saturating_mul(storage))
    {
        return Err(Error::format(
            path,
            format!(
                "{name} claims {n_values} values ({claimed} bytes) stored in {storage} bytes of a \
                 {file_len}-byte file: its dataspace or chunk index is corrupt"
            ),
        ));
    }
    Ok(n_values)
}

/// Read a string dataset of any of the types cooler, HiCExplorer (PyTables) and h5py write:
/// variable-length UTF-8 or ASCII, fixed-length ASCII or UTF-8 (at most 1,024 bytes, trailing
/// NULs removed), under the deadline. Another type is an error naming `name`.
pub fn read_strings(path: &str, dataset: &hdf5::Dataset, name: &str) -> Result<Vec<String>> {
    use hdf5::types::{FixedAscii, FixedUnicode, TypeDescriptor, VarLenAscii, VarLenUnicode};
    let err = |e| Error::hdf5(path, format!("reading {name}"), e);
    let descriptor = guarded(path, name, || {
        dataset.dtype().and_then(|t| t.to_descriptor())
    })
    .map_err(|e| Error::hdf5(path, format!("reading the type of {name}"), e))?;
    guarded(path, name, || -> Result<Vec<String>> {
        let trimmed = |s: &str| s.trim_end_matches('\0').to_string();
        Ok(match descriptor {
            TypeDescriptor::VarLenUnicode => dataset
                .read_raw::<VarLenUnicode>()
                .map_err(err)?
                .iter()
                .map(|s| lossy(s.as_bytes()))
                .collect(),
            TypeDescriptor::VarLenAscii => dataset
                .read_raw::<VarLenAscii>()
                .map_err(err)?
                .iter()
                .map(|s| lossy(s.as_bytes()))
                .collect(),
            TypeDescriptor::FixedAscii(_) => dataset
                .read_raw::<FixedAscii<1024>>()
                .map_err(err)?
                .iter()
                .map(|s| trimmed(&lossy(s.as_bytes())))
                .collect(),
            TypeDescriptor::FixedUnicode(_) => dataset
                .read_raw::<FixedUnicode<1024>>()
                .map_err(err)?
                .iter()
                .map(|s| trimmed(&lossy(s.as_bytes())))
                .collect(),
            other => {
                return Err(Error::format(
                    path,
                    format!("{name} has type {other:?}; expected strings"),
                ));
            }
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    static FIRED: AtomicUsize = AtomicUsize::new(0);
    static LAST: Mutex<String> = Mutex::new(String::new());

    fn record(message: &str) {
        FIRED.fetch_add(1, Ordering::SeqCst);
        *LAST.lock().unwrap() = message.to_string();
    }

    #[test]
    fn a_slow_call_fires_the_handler_once_and_a_fast_one_never() {
        set_timeout_handler(record);
        let before = FIRED.load(Ordering::SeqCst);
        let value = guarded_for(Duration::from_millis(500), "fast.cool", "attrs", || 7);
        assert_eq!(value, 7);
        std::thread::sleep(Duration::from_millis(700));
        assert_eq!(FIRED.load(Ordering::SeqCst), before, "a fast call fired");
        guarded_for(
            Duration::from_millis(50),
            "slow.cool",
            "attribute 'format'",
            || std::thread::sleep(Duration::from_millis(400)),
        );
        std::thread::sleep(Duration::from_millis(100));
        assert_eq!(FIRED.load(Ordering::SeqCst), before + 1);
        let last = LAST.lock().unwrap().clone();
        assert!(last.starts_with("slow.cool: HDF5 reading attribute 'format' did not finish"));
    }
}
