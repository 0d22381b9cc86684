//! How pandas reads a pairs field, as pairtools' `dedup` and `stats` see it through
//! `pd.read_table`: the strings it takes for a missing value.

/// The strings pandas reads as missing (`na_values`' defaults).
pub const NA_VALUES: [&[u8]; 19] = [
    b"",
    b"#N/A",
    b"#N/A N/A",
    b"#NA",
    b"-1.#IND",
    b"-1.#QNAN",
    b"-NaN",
    b"-nan",
    b"1.#IND",
    b"1.#QNAN",
    b"<NA>",
    b"N/A",
    b"NA",
    b"NULL",
    b"NaN",
    b"None",
    b"n/a",
    b"nan",
    b"null",
];

/// Whether pandas reads `value` as missing.
pub fn is_na(value: &[u8]) -> bool {
    // Most values (chromosomes, positions, strands, read names) are told apart by their first
    // bytes or their length before any comparison. Strands (`-`) and positions (`1...`) are common: the missing values that start with `-`
    // are at least four bytes long, those that start with `1` go on with `.`.
    match value {
        [] => true,
        [b'-', _, _, _, ..] | [b'1', b'.', ..] | [b'#' | b'<' | b'N' | b'n', ..]
            if value.len() <= 9 =>
        {
            NA_VALUES.contains(&value)
        }
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fast_test_agrees_with_the_list() {
        for value in NA_VALUES {
            assert!(is_na(value), "{value:?}");
        }
        for value in [
            &b"chr1"[..],
            b"123",
            b"1",
            b"+",
            b"-",
            b"NAN",
            b"nul",
            b"None ",
            b"-",
            b"-1",
            b"-NA",
            b"1.5",
            b"12",
            b"1.#INF",
        ] {
            assert_eq!(is_na(value), NA_VALUES.contains(&value), "{value:?}");
        }
    }

    proptest::proptest! {
        #[test]
        fn the_fast_test_agrees_with_the_list_on_any_short_value(
            value in proptest::collection::vec(
                proptest::sample::select(b"#-1.<>/NAIDQnaulo \t".to_vec()), 0..10)
        ) {
            proptest::prop_assert_eq!(is_na(&value), NA_VALUES.contains(&value.as_slice()));
        }
    }
}
