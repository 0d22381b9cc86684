//! Matrix URIs: a file path, then, after `::`, the group that holds the matrix in it
//! (`file.mcool::/resolutions/1000`, `file.hic::/resolutions/N`).

use crate::error::{Error, Result};

/// Split `cool.mcool::/resolutions/1000` into the file path and the group path (if any).
pub fn split_uri(uri: &str) -> (&str, Option<&str>) {
    match uri.split_once("::") {
        Some((path, group)) => (path, Some(group)),
        None => (uri, None),
    }
}

/// Parse `/resolutions/N` (or a bare `N`) in a URI.
pub fn parse_resolution_group(uri: &str, group: &str) -> Result<u64> {
    let trimmed = group.trim_start_matches('/');
    let number = trimmed.strip_prefix("resolutions/").unwrap_or(trimmed);
    number.parse::<u64>().map_err(|_| {
        Error::format(
            uri,
            format!("'{group}' is not a resolution path (expected /resolutions/<bin size>)"),
        )
    })
}
