//! Conditions on pairs records, for `contactmap pairs select CONDITION` (pairtools 1.1.2's
//! `pairtools select`).
//!
//! pairtools evaluates the condition as Python, with each column name replaced by the record's
//! field; this module parses a small language that covers what users write there, checks it
//! against the header's columns once, and evaluates it per record without Python.
//!
//! # Syntax
//!
//! Python's syntax and precedence for the subset below (from the loosest binding to the
//! tightest):
//!
//! | form | meaning |
//! |---|---|
//! | `A or B` | either condition (B is not evaluated when A holds) |
//! | `A and B` | both conditions (B is not evaluated when A fails) |
//! | `not A` | the opposite condition |
//! | `X == Y`, `!=`, `<`, `<=`, `>`, `>=` | comparisons, chained as in Python (`0 < pos1 < 1000`) |
//! | `X in (V, ...)`, `X not in [V, ...]` | membership in a tuple or list (`("UU",)` has one element) |
//! | `X in "TEXT"` | `X` is a substring of `TEXT` (Python's meaning, also for `X in ("UU")`) |
//! | `X + Y`, `X - Y` | sums of numbers |
//! | `X * Y`, `X / Y`, `X // Y`, `X % Y` | products, division (a float), floor division, remainder |
//! | `-X`, `+X` | signs |
//! | `( ... )` | grouping |
//!
//! Values: a column of the header by its name (`chrom1`, `pair_type`, `mapq1`, any other),
//! `COLS[i]` (field `i`, 0-based, as text), strings in single or double quotes (with `\\`,
//! `\'`, `\"`, `\n`, `\t` escapes; `r"..."` raw), integers (`100000`, `1_000`), floats
//! (`1e6`, `0.5`), `True`, `False`, and the functions `abs(X)`,
//! `csv_match(X, "a,b,c")` (`X` is one of the comma-separated values) and
//! `wildcard_match(X, "C*")` (a shell pattern over the whole of `X`: `*`, `?`, `[abc]`,
//! `[!abc]`, byte by byte).
//!
//! # Types
//!
//! As pairtools reads them, `pos1`, `pos2` and the integer columns of pairtools' extra columns
//! (`mapq`, `pos5`, `pos3`, `read_len`, `matched_bp`, `algn_ref_span`, `algn_read_span`,
//! `dist_to_5`, `dist_to_3`, `read_side`, `algn_idx`, `same_side_algn_count`, each with suffix
//! `1` or `2`) are numbers; every other column is text ([`default_column_type`];
//! [`Selection::parse_with_types`] changes it, as pairtools' `--type-cast`). Numbers compare
//! with numbers and text with text (byte order, which is code-point order for UTF-8).
//!
//! # Differences from pairtools
//!
//! The condition is not arbitrary Python: no other functions or methods, no `--startup-code`,
//! no `regex_match` (the crate has no regular expressions). The types are checked when the
//! condition is parsed, where Python fails (or silently compares unequal) record by record:
//! comparing a text column with a number (`mapq1 == "30"`, `chrom1 > 5`) is an error naming
//! the column, and so is a condition that is not true or false (a bare column, a number);
//! `and`, `or` and `not` take conditions, not Python's truthy values. pairtools reads only
//! `pos1`, `pos2`, `mapq1` and `mapq2` as integers unless told (`-t read_len1 int`); here the
//! other integer extra columns are numbers too. A numeric field that is not an integer (a float
//! for a float column) is an error of that record ([`Selection::matches`]).

mod parse;
#[cfg(test)]
mod tests;
mod tree;

use crate::error::Result;
use crate::io::pairs::PairRecord;

use tree::*;
pub use tree::{ColumnType, default_column_type};

/// A parsed condition, ready to be evaluated on the records of a file with the columns it was
/// parsed for.
#[derive(Clone, Debug)]
pub struct Selection {
    expression: String,
    root: Node,
}

impl Selection {
    /// Parse `expression` for records with `columns` (the header's `#columns:` names), with
    /// the default column types ([`default_column_type`]). Errors ([`crate::Error::Argument`]) give the
    /// character position in the expression and what was expected there: a syntax error, an
    /// unknown column or function, a comparison of text with a number, a condition that is not
    /// true or false.
    pub fn parse(expression: &str, columns: &[String]) -> Result<Selection> {
        Selection::parse_with_types(expression, columns, &[])
    }

    /// [`Selection::parse`] with the types of some columns given (`pairtools select -t NAME
    /// TYPE`); the others keep their default.
    pub fn parse_with_types(
        expression: &str,
        columns: &[String],
        types: &[(String, ColumnType)],
    ) -> Result<Selection> {
        let root = parse::parse(expression, columns, types)?;
        Ok(Selection {
            expression: expression.to_string(),
            root,
        })
    }

    /// The expression as given.
    pub fn expression(&self) -> &str {
        &self.expression
    }

    /// Whether `record` is selected. The error (for the caller to name the line with) is a
    /// numeric column whose field is not a number, a missing field, an integer overflow or a
    /// division by zero.
    pub fn matches(&self, record: &PairRecord) -> std::result::Result<bool, String> {
        match self.root.evaluate(record)? {
            Value::Bool(selected) => Ok(selected),
            _ => unreachable!("the root is checked to be a condition"),
        }
    }
}
