//! The condition's tree and its evaluation on a record: the types [`super::Selection`] and
//! the parser share.

use std::collections::HashSet;

use crate::io::pairs::PairRecord;
use crate::pairs::parse::EXTRA_COLUMNS;

/// How a column's fields are read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColumnType {
    /// An integer (Python's `int(field)`: surrounding spaces and a sign allowed).
    Integer,
    /// A float (Python's `float(field)`).
    Float,
    /// Text, compared byte by byte.
    Text,
}

/// The extra columns pairtools reads as text; the others of [`EXTRA_COLUMNS`] it reads as
/// integers (its `DTYPES_EXTRA_COLUMNS`).
const TEXT_EXTRA_COLUMNS: [&str; 3] = ["cigar", "seq", "mismatches"];

/// How a column is read by default: `pos1`, `pos2` and the integer extra columns with suffix
/// `1` or `2` as integers, everything else as text.
pub fn default_column_type(name: &str) -> ColumnType {
    if name == "pos1" || name == "pos2" {
        return ColumnType::Integer;
    }
    match name.strip_suffix(['1', '2']) {
        Some(base) if EXTRA_COLUMNS.contains(&base) && !TEXT_EXTRA_COLUMNS.contains(&base) => {
            ColumnType::Integer
        }
        _ => ColumnType::Text,
    }
}

/// The static type of an expression.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Type {
    Bool,
    Number,
    Text,
    /// A tuple or list: only after `in`.
    List,
}

/// A number as Python keeps it: an integer or a float.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Number {
    Int(i64),
    Float(f64),
}

impl Number {
    pub(crate) fn as_f64(self) -> f64 {
        match self {
            Number::Int(i) => i as f64,
            Number::Float(x) => x,
        }
    }

    pub(crate) fn compare(self, other: Number) -> Option<std::cmp::Ordering> {
        match (self, other) {
            (Number::Int(a), Number::Int(b)) => Some(a.cmp(&b)),
            (a, b) => a.as_f64().partial_cmp(&b.as_f64()),
        }
    }

    pub(crate) fn arithmetic(
        self,
        op: Arithmetic,
        other: Number,
    ) -> std::result::Result<Number, String> {
        use Arithmetic::*;
        let overflow = || format!("integer overflow in {} {} {}", self, op.symbol(), other);
        let by_zero = || format!("division by zero in {} {} {}", self, op.symbol(), other);
        if let (Number::Int(a), Number::Int(b)) = (self, other) {
            let result = match op {
                Add => a.checked_add(b),
                Subtract => a.checked_sub(b),
                Multiply => a.checked_mul(b),
                Divide => None,
                FloorDivide | Remainder if b == 0 => return Err(by_zero()),
                FloorDivide => a.checked_div_euclid(b).map(|q| {
                    // Python floors towards minus infinity.
                    if b < 0 && a.rem_euclid(b) != 0 {
                        q + 1
                    } else {
                        q
                    }
                }),
                Remainder => a.checked_rem_euclid(b).map(|r| {
                    // Python's remainder has the sign of the divisor.
                    if b < 0 && r != 0 { r + b } else { r }
                }),
            };
            if op != Divide {
                return result.map(Number::Int).ok_or_else(overflow);
            }
        }
        let (a, b) = (self.as_f64(), other.as_f64());
        if b == 0.0 && matches!(op, Divide | FloorDivide | Remainder) {
            return Err(by_zero());
        }
        Ok(Number::Float(match op {
            Add => a + b,
            Subtract => a - b,
            Multiply => a * b,
            Divide => a / b,
            FloorDivide => (a / b).floor(),
            Remainder => {
                let r = a % b;
                if r != 0.0 && (r < 0.0) != (b < 0.0) {
                    r + b
                } else {
                    r
                }
            }
        }))
    }
}

impl std::fmt::Display for Number {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Number::Int(i) => write!(f, "{i}"),
            Number::Float(x) => write!(f, "{x}"),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Comparison {
    Equal,
    NotEqual,
    Less,
    LessEqual,
    Greater,
    GreaterEqual,
    In,
    NotIn,
}

impl Comparison {
    pub(crate) fn holds(self, ordering: Option<std::cmp::Ordering>) -> bool {
        use std::cmp::Ordering::*;
        match self {
            Comparison::Equal => ordering == Some(Equal),
            Comparison::NotEqual => ordering != Some(Equal),
            Comparison::Less => ordering == Some(Less),
            Comparison::LessEqual => matches!(ordering, Some(Less | Equal)),
            Comparison::Greater => ordering == Some(Greater),
            Comparison::GreaterEqual => matches!(ordering, Some(Greater | Equal)),
            Comparison::In | Comparison::NotIn => unreachable!("membership is not an ordering"),
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Arithmetic {
    Add,
    Subtract,
    Multiply,
    Divide,
    FloorDivide,
    Remainder,
}

impl Arithmetic {
    pub(crate) fn symbol(self) -> &'static str {
        match self {
            Arithmetic::Add => "+",
            Arithmetic::Subtract => "-",
            Arithmetic::Multiply => "*",
            Arithmetic::Divide => "/",
            Arithmetic::FloorDivide => "//",
            Arithmetic::Remainder => "%",
        }
    }
}

/// A parsed expression.
#[derive(Clone, Debug)]
pub(crate) enum Node {
    Bool(bool),
    Number(Number),
    Text(Vec<u8>),
    Column {
        index: usize,
        name: String,
        column_type: ColumnType,
    },
    List(Vec<Node>),
    Not(Box<Node>),
    And(Box<Node>, Box<Node>),
    Or(Box<Node>, Box<Node>),
    /// `first op1 second op2 third ...`: every link must hold (Python's chained comparisons).
    Compare(Box<Node>, Vec<(Comparison, Node)>),
    Arithmetic(Arithmetic, Box<Node>, Box<Node>),
    Negate(Box<Node>),
    Abs(Box<Node>),
    CsvMatch(Box<Node>, HashSet<Vec<u8>>),
    WildcardMatch(Box<Node>, Vec<u8>),
}

/// A value while evaluating.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Value<'a> {
    Bool(bool),
    Number(Number),
    Text(&'a [u8]),
    List(Vec<Value<'a>>),
}

impl Node {
    pub(crate) fn evaluate<'a>(
        &'a self,
        record: &'a PairRecord,
    ) -> std::result::Result<Value<'a>, String> {
        Ok(match self {
            Node::Bool(b) => Value::Bool(*b),
            Node::Number(n) => Value::Number(*n),
            Node::Text(t) => Value::Text(t),
            Node::Column {
                index,
                name,
                column_type,
            } => {
                if *index >= record.len() {
                    return Err(format!(
                        "no field for column '{name}' (field {}): the line has {}",
                        index + 1,
                        record.len()
                    ));
                }
                let field = record.field(*index);
                match column_type {
                    ColumnType::Text => Value::Text(field),
                    ColumnType::Integer => Value::Number(Number::Int(
                        parse_integer(field)
                            .ok_or_else(|| not_a_number(name, field, "an integer"))?,
                    )),
                    ColumnType::Float => Value::Number(Number::Float(
                        parse_float(field).ok_or_else(|| not_a_number(name, field, "a number"))?,
                    )),
                }
            }
            Node::List(items) => Value::List(
                items
                    .iter()
                    .map(|item| item.evaluate(record))
                    .collect::<std::result::Result<_, _>>()?,
            ),
            Node::Not(a) => Value::Bool(!a.condition(record)?),
            Node::And(a, b) => Value::Bool(a.condition(record)? && b.condition(record)?),
            Node::Or(a, b) => Value::Bool(a.condition(record)? || b.condition(record)?),
            Node::Compare(first, links) => {
                let mut left = first.evaluate(record)?;
                for (op, node) in links {
                    let right = node.evaluate(record)?;
                    if !compare(&left, *op, &right) {
                        return Ok(Value::Bool(false));
                    }
                    left = right;
                }
                Value::Bool(true)
            }
            Node::Arithmetic(op, a, b) => {
                Value::Number(a.number(record)?.arithmetic(*op, b.number(record)?)?)
            }
            Node::Negate(a) => Value::Number(match a.number(record)? {
                Number::Int(i) => Number::Int(
                    i.checked_neg()
                        .ok_or_else(|| format!("integer overflow in -{i}"))?,
                ),
                Number::Float(x) => Number::Float(-x),
            }),
            Node::Abs(a) => Value::Number(match a.number(record)? {
                Number::Int(i) => Number::Int(
                    i.checked_abs()
                        .ok_or_else(|| format!("integer overflow in abs({i})"))?,
                ),
                Number::Float(x) => Number::Float(x.abs()),
            }),
            Node::CsvMatch(a, values) => Value::Bool(values.contains(a.text(record)?)),
            Node::WildcardMatch(a, pattern) => {
                Value::Bool(wildcard_match(a.text(record)?, pattern))
            }
        })
    }

    pub(crate) fn condition(&self, record: &PairRecord) -> std::result::Result<bool, String> {
        match self.evaluate(record)? {
            Value::Bool(b) => Ok(b),
            other => unreachable!("a condition is checked to be true or false: {other:?}"),
        }
    }

    pub(crate) fn number(&self, record: &PairRecord) -> std::result::Result<Number, String> {
        match self.evaluate(record)? {
            Value::Number(n) => Ok(n),
            other => unreachable!("checked to be a number: {other:?}"),
        }
    }

    pub(crate) fn text<'a>(
        &'a self,
        record: &'a PairRecord,
    ) -> std::result::Result<&'a [u8], String> {
        match self.evaluate(record)? {
            Value::Text(t) => Ok(t),
            other => unreachable!("checked to be text: {other:?}"),
        }
    }
}

pub(crate) fn not_a_number(name: &str, field: &[u8], what: &str) -> String {
    format!(
        "column '{name}': '{}' is not {what}",
        String::from_utf8_lossy(field)
    )
}

/// `left op right` for two values of types the parser allowed together.
pub(crate) fn compare(left: &Value, op: Comparison, right: &Value) -> bool {
    match op {
        Comparison::In | Comparison::NotIn => {
            let found = match right {
                Value::List(items) => items
                    .iter()
                    .any(|item| compare(left, Comparison::Equal, item)),
                Value::Text(haystack) => match left {
                    Value::Text(needle) => contains(haystack, needle),
                    _ => false,
                },
                _ => false,
            };
            found == (op == Comparison::In)
        }
        _ => {
            let ordering = match (left, right) {
                (Value::Number(a), Value::Number(b)) => a.compare(*b),
                (Value::Text(a), Value::Text(b)) => Some(a.cmp(b)),
                (Value::Bool(a), Value::Bool(b)) => Some(a.cmp(b)),
                _ => None,
            };
            op.holds(ordering)
        }
    }
}

pub(crate) fn contains(haystack: &[u8], needle: &[u8]) -> bool {
    needle.is_empty() || haystack.windows(needle.len()).any(|w| w == needle)
}

/// Python's `int(field)`: surrounding whitespace, an optional sign, decimal digits (single
/// underscores between them).
pub(crate) fn parse_integer(field: &[u8]) -> Option<i64> {
    let text = std::str::from_utf8(field).ok()?.trim();
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if digits.is_empty()
        || digits.starts_with('_')
        || digits.ends_with('_')
        || digits.contains("__")
        || !digits.bytes().all(|b| b.is_ascii_digit() || b == b'_')
    {
        return None;
    }
    text.replace('_', "").parse().ok()
}

/// Python's `float(field)` (decimal and exponent forms, `nan`, `inf`).
pub(crate) fn parse_float(field: &[u8]) -> Option<f64> {
    let text = std::str::from_utf8(field).ok()?.trim();
    if text.contains("__") || text.starts_with('_') || text.ends_with('_') {
        return None;
    }
    text.replace('_', "").parse().ok()
}

/// fnmatch's shell pattern over the whole of `text`, byte by byte: `*` any run, `?` one byte,
/// `[abc]` / `[a-z]` / `[!abc]` a set (an unclosed `[` is literal), anything else itself.
pub(crate) fn wildcard_match(text: &[u8], pattern: &[u8]) -> bool {
    // Backtracking over the last `*` (linear in practice for shell patterns).
    let (mut t, mut p) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while t < text.len() {
        if p < pattern.len() {
            match pattern[p] {
                b'*' => {
                    star = Some((p, t));
                    p += 1;
                    continue;
                }
                b'?' => {
                    t += 1;
                    p += 1;
                    continue;
                }
                b'[' => {
                    if let Some((matched, next)) = match_set(&pattern[p..], text[t]) {
                        if matched {
                            t += 1;
                            p += next;
                            continue;
                        }
                    } else if text[t] == b'[' {
                        t += 1;
                        p += 1;
                        continue;
                    }
                }
                byte if byte == text[t] => {
                    t += 1;
                    p += 1;
                    continue;
                }
                _ => {}
            }
        }
        match star {
            Some((star_p, star_t)) => {
                p = star_p + 1;
                t = star_t + 1;
                star = Some((star_p, star_t + 1));
            }
            None => return false,
        }
    }
    pattern[p..].iter().all(|&b| b == b'*')
}

/// Whether `byte` is in the set that `pattern` (starting with `[`) opens, and the set's
/// length; `None` when the set is not closed.
pub(crate) fn match_set(pattern: &[u8], byte: u8) -> Option<(bool, usize)> {
    let mut i = 1;
    let negated = pattern.get(i) == Some(&b'!');
    if negated {
        i += 1;
    }
    // A ']' first in the set is a member.
    let start = i;
    let mut found = false;
    loop {
        let c = *pattern.get(i)?;
        if c == b']' && i > start {
            return Some((found != negated, i + 1));
        }
        if pattern.get(i + 1) == Some(&b'-') && pattern.get(i + 2).is_some_and(|&e| e != b']') {
            let end = pattern[i + 2];
            found |= c <= byte && byte <= end;
            i += 3;
        } else {
            found |= c == byte;
            i += 1;
        }
    }
}
