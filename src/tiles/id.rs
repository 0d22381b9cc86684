//! Tile ids as HiGlass writes them: `UID.z.x.y[.transform]` for a map's 2D tiles, `UID.z.x` for
//! a 1D track's; what a request may name, checked before anything is looked up.

/// A tile a request names: `UID.z.x.y` (a map's) or `UID.z.x` (a 1D track's), with an optional
/// `.transform`.
#[derive(Debug, PartialEq, Eq)]
pub struct TileId<'a> {
    /// The tileset's UID: letters, digits, `-` and `_`.
    pub uid: &'a str,
    /// The zoom level (0 the coarsest), at most 64.
    pub zoom: usize,
    /// The tile's column (its position along the genome for a 1D track).
    pub x: u64,
    /// The tile's row, for a map's 2D tile.
    pub y: Option<u64>,
    /// The transform (`KR`, `weight` ...) or a track's aggregation, when given.
    pub transform: Option<&'a str>,
}

impl<'a> TileId<'a> {
    /// Parse a tile id as HiGlass writes it, or say what is wrong with it (the id quoted, at
    /// most 64 characters of it).
    ///
    /// ```
    /// use contactmap::tiles::TileId;
    ///
    /// let tile = TileId::parse("GM12878.3.5.7.KR")?;
    /// assert_eq!((tile.uid, tile.zoom, tile.x, tile.y, tile.transform), ("GM12878", 3, 5, Some(7), Some("KR")));
    /// assert_eq!(TileId::parse("domains.2.1")?.y, None);
    /// assert!(TileId::parse("../etc/passwd.0.0.0").is_err());
    /// # Ok::<(), String>(())
    /// ```
    pub fn parse(id: &'a str) -> Result<TileId<'a>, String> {
        let parts: Vec<&str> = id.split('.').collect();
        let numeric = |t: &&str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
        // UID, z, x, then y when it is a number, then the transform
        let has_y = parts.get(3).is_some_and(numeric);
        let n_max = if has_y { 5 } else { 4 };
        if parts.len() < 3 || parts.len() > n_max {
            return Err(format!(
                "tile id '{}': expected UID.z.x.y[.transform] (a map) or UID.z.x (a track)",
                shown(id)
            ));
        }
        let uid = parts[0];
        if !is_name(uid, 128) {
            return Err(format!("tile id '{}': not a tileset UID", shown(id)));
        }
        let number = |text: &str, what: &str| {
            let digits = numeric(&text) && text.len() <= 19;
            digits
                .then(|| text.parse::<u64>().ok())
                .flatten()
                .ok_or_else(|| {
                    format!(
                        "tile id '{}': {what} '{}' is not a number",
                        shown(id),
                        shown(text)
                    )
                })
        };
        let zoom = number(parts[1], "zoom level")?;
        if zoom > 64 {
            return Err(format!(
                "tile id '{}': zoom level {zoom} is beyond 64",
                shown(id)
            ));
        }
        let x = number(parts[2], "x")?;
        let y = if has_y {
            Some(number(parts[3], "y")?)
        } else {
            None
        };
        let transform = match parts.get(if has_y { 4 } else { 3 }) {
            Some(t) if is_name(t, 32) => Some(*t),
            Some(t) => {
                return Err(format!(
                    "tile id '{}': '{}' is not a transform",
                    shown(id),
                    shown(t)
                ));
            }
            None => None,
        };
        Ok(TileId {
            uid,
            zoom: zoom as usize,
            x,
            y,
            transform,
        })
    }
}

/// Letters, digits, `-` and `_`, 1 to `max` of them.
fn is_name(text: &str, max: usize) -> bool {
    (1..=max).contains(&text.len())
        && text
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_')
}

/// A request's text as an error message shows it: at most 64 characters, controls escaped.
pub fn shown(text: &str) -> String {
    let mut out: String = text
        .chars()
        .take(64)
        .flat_map(char::escape_default)
        .collect();
    if text.chars().count() > 64 {
        out.push_str("...");
    }
    out
}
