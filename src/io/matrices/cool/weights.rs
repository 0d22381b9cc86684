//! Weight columns as cooler reads them: the columns divisive by their name alone.

/// Weight columns that cooler itself reads as divisive, by name (`cooler.api._4DN_DIVISIVE_WEIGHTS`).
pub const DIVISIVE_BY_NAME: [&str; 3] = ["KR", "VC", "VC_SQRT"];
