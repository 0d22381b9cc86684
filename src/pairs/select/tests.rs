use super::*;
use crate::io::pairs::PairsReader;

use crate::pairs::tests::reference;

/// The records of pairs text (its lines after the header).
fn body(text: &str) -> Vec<&str> {
    text.lines().filter(|l| !l.starts_with('#')).collect()
}

/// The lines of the records of pairs text that `expression` selects.
fn selected_lines(text: &str, name: &str, expression: &str) -> Vec<String> {
    let input = std::io::Cursor::new(text.as_bytes().to_vec());
    let mut reader = PairsReader::new(Box::new(input), name).unwrap();
    let selection = Selection::parse(expression, &reader.header().columns())
        .unwrap_or_else(|e| panic!("{expression}: {e}"));
    let mut selected = Vec::new();
    let mut record = PairRecord::default();
    while reader.read_record(&mut record).unwrap() {
        if selection.matches(&record).unwrap() {
            selected.push(String::from_utf8(record.line().to_vec()).unwrap());
        }
    }
    selected
}

fn columns() -> Vec<String> {
    "readID chrom1 pos1 chrom2 pos2 strand1 strand2 pair_type mapq1 mapq2"
        .split(' ')
        .map(String::from)
        .collect()
}

fn record(
    chrom1: &str,
    pos1: i64,
    chrom2: &str,
    pos2: i64,
    pair_type: &str,
    mapq1: i64,
) -> PairRecord {
    let line = format!("r\t{chrom1}\t{pos1}\t{chrom2}\t{pos2}\t+\t-\t{pair_type}\t{mapq1}\t60");
    PairRecord::from_line(line.as_bytes(), 1)
}

fn select(expression: &str, record: &PairRecord) -> bool {
    Selection::parse(expression, &columns())
        .unwrap_or_else(|e| panic!("{expression}: {e}"))
        .matches(record)
        .unwrap()
}

fn parse_error(expression: &str) -> String {
    Selection::parse(expression, &columns())
        .unwrap_err()
        .to_string()
}

#[test]
fn selections_match_pairtools() {
    for (input, expression, expected) in [
        (
            "sim.5any.pairs.gz",
            r#"(pair_type=="UU") or (pair_type=="UR") or (pair_type=="RU")"#,
            "sim.select_uu_ur_ru.pairs.gz",
        ),
        (
            "sim.5unique.full.pairs.gz",
            "(chrom1!=chrom2) and (mapq1>=30) and (mapq2>=30)",
            "sim.select_trans_mapq30.pairs.gz",
        ),
    ] {
        let text = reference(input);
        let selected = selected_lines(&text, input, expression);
        let expected = reference(expected);
        let expected = body(&expected);
        let n = body(&text).len();
        assert!(!expected.is_empty() && expected.len() < n, "{expression}");
        assert_eq!(selected, expected, "{input}: {expression}");
    }
}

/// A record's fields by column name, for the naive evaluations.
struct Fields<'a> {
    columns: &'a [String],
    fields: Vec<&'a str>,
}

impl Fields<'_> {
    fn text(&self, column: &str) -> &str {
        let i = self.columns.iter().position(|c| c == column).unwrap();
        self.fields[i]
    }

    fn int(&self, column: &str) -> i64 {
        self.text(column).parse().unwrap()
    }
}

#[test]
fn selections_match_a_naive_evaluation() {
    // pairtools parse's 5unique pairs with every alignment column (mapq1, mapq2), each
    // expression against the same condition written in Rust.
    type Naive = fn(&Fields) -> bool;
    let cases: [(&str, Naive); 5] = [
        ("chrom1 == chrom2 and mapq1 >= 30", |r| {
            r.text("chrom1") == r.text("chrom2") && r.int("mapq1") >= 30
        }),
        (r#"not (chrom1 == "!")"#, |r| r.text("chrom1") != "!"),
        (r#"pos1 < 100000 and strand1 == "+""#, |r| {
            r.int("pos1") < 100_000 && r.text("strand1") == "+"
        }),
        (
            r#"pair_type in ("UU", "RU") and abs(pos1 - pos2) < 2e4"#,
            |r| {
                ["UU", "RU"].contains(&r.text("pair_type"))
                    && (r.int("pos1") - r.int("pos2")).abs() < 20_000
            },
        ),
        (
            r#"wildcard_match(pair_type, "*U") or csv_match(chrom2, "chr2,chrX") and not mapq1 + mapq2 > 60"#,
            |r| {
                r.text("pair_type").ends_with('U')
                    || (["chr2", "chrX"].contains(&r.text("chrom2"))
                        && r.int("mapq1") + r.int("mapq2") <= 60)
            },
        ),
    ];
    let text = reference("sim.5unique.full.pairs.gz");
    let input = std::io::Cursor::new(text.as_bytes().to_vec());
    let columns = PairsReader::new(Box::new(input), "full.pairs")
        .unwrap()
        .header()
        .columns();
    let records = body(&text);
    for (expression, naive) in cases {
        let expected: Vec<&str> = records
            .iter()
            .copied()
            .filter(|line| {
                naive(&Fields {
                    columns: &columns,
                    fields: line.split('\t').collect(),
                })
            })
            .collect();
        assert!(
            !expected.is_empty() && expected.len() < records.len(),
            "{expression}"
        );
        let selected = selected_lines(&text, "full.pairs", expression);
        assert_eq!(selected, expected, "{expression}");
    }
}

#[test]
fn comparisons_of_numbers_and_text() {
    let r = record("chr1", 100, "chr2", 5000, "UU", 30);
    for (expression, expected) in [
        ("pos1 == 100", true),
        ("pos1 != 100", false),
        ("pos1 < 101", true),
        ("pos1 <= 100", true),
        ("pos1 > 100", false),
        ("pos1 >= 100.0", true),
        ("pos1 < 1e2", false),
        ("0 < pos1 < pos2 < 10_000", true),
        ("pos1 < pos2 < 10", false),
        ("chrom1 < chrom2", true),
        ("chrom1 >= 'chr10'", false),
        ("chrom1 == 'chr1'", true),
        ("chrom1 == COLS[3]", false),
        ("COLS[1] == 'chr1'", true),
        ("True", true),
        ("False or pos1 == 100", true),
        ("(pos1 == 100) == True", true),
    ] {
        assert_eq!(select(expression, &r), expected, "{expression}");
    }
}

#[test]
fn membership_arithmetic_and_functions() {
    let r = record("chr1", 100, "chr1", 5000, "RU", 30);
    for (expression, expected) in [
        ("pair_type in ('UU', 'RU')", true),
        ("pair_type in ['UU', 'UR']", false),
        ("pair_type not in ('UU',)", true),
        ("pair_type in ('RU',)", true),
        ("pair_type in ()", false),
        ("pair_type in ('RUU')", true), // a string, as in Python: substring
        ("'U' in pair_type", true),
        ("mapq1 in (29, 30, 31)", true),
        ("mapq1 in (-30, 60)", false),
        ("pos2 - pos1 == 4900", true),
        ("pos1 - pos2 == -4900", true),
        ("abs(pos1 - pos2) == 4900", true),
        ("pos2 / pos1 == 50", true),
        ("pos2 // 3 == 1666", true),
        ("-pos2 // 3 == -1667", true),
        ("pos2 % 3 == 2", true),
        ("-pos2 % 3 == 1", true),
        ("pos2 % -3 == -1", true),
        ("pos1 * 2 + 1 == 201", true),
        ("pos1 + 2 * 3 == 106", true),
        ("(pos1 + 2) * 3 == 306", true),
        ("-(pos1) == -100", true),
        ("csv_match(chrom1, 'chr2,chr1')", true),
        ("csv_match(chrom1, 'chr10,chr2')", false),
        ("wildcard_match(pair_type, 'R?')", true),
        ("wildcard_match(pair_type, '[!U]*')", true),
        ("wildcard_match(chrom1, 'chr[0-9]')", true),
        ("wildcard_match(chrom1, 'chr')", false),
        ("wildcard_match(chrom1, '*1*')", true),
    ] {
        assert_eq!(select(expression, &r), expected, "{expression}");
    }
}

#[test]
fn wildcards_follow_fnmatch() {
    for (text, pattern, expected) in [
        ("", "*", true),
        ("", "?", false),
        ("abc", "a*c", true),
        ("abcbc", "a*bc", true),
        ("abcbd", "a*bc", false),
        ("a[b", "a[b", true),
        ("a]", "a[]]", true),
        ("a-", "a[-x]", true),
        ("ab", "a[!b]", false),
        ("chr12", "chr*2", true),
        ("x", "[a-c]", false),
    ] {
        assert_eq!(
            wildcard_match(text.as_bytes(), pattern.as_bytes()),
            expected,
            "{text} {pattern}"
        );
    }
}

/// A condition tree for the precedence test, rendered with as few parentheses as Python's
/// precedence allows.
#[derive(Clone, Debug)]
enum Tree {
    Atom(usize),
    Not(Box<Tree>),
    And(Box<Tree>, Box<Tree>),
    Or(Box<Tree>, Box<Tree>),
}

const ATOMS: [(&str, bool); 6] = [
    ("pos1 < 200", true),
    ("chrom1 == 'chr2'", false),
    ("mapq1 >= 30", true),
    ("pair_type in ('NN', 'WW')", false),
    ("True", true),
    ("pos2 != 5000", false),
];

impl Tree {
    fn evaluate(&self) -> bool {
        match self {
            Tree::Atom(i) => ATOMS[*i].1,
            Tree::Not(a) => !a.evaluate(),
            Tree::And(a, b) => a.evaluate() && b.evaluate(),
            Tree::Or(a, b) => a.evaluate() || b.evaluate(),
        }
    }

    /// 0: or, 1: and, 2: not, 3: atom.
    fn level(&self) -> u8 {
        match self {
            Tree::Or(..) => 0,
            Tree::And(..) => 1,
            Tree::Not(_) => 2,
            Tree::Atom(_) => 3,
        }
    }

    fn render(&self, extra_parens: &mut dyn FnMut() -> bool) -> String {
        let child = |tree: &Tree, min_level: u8, extra: &mut dyn FnMut() -> bool| {
            let text = tree.render(extra);
            if tree.level() < min_level || extra() {
                format!("({text})")
            } else {
                text
            }
        };
        match self {
            Tree::Atom(i) => ATOMS[*i].0.to_string(),
            Tree::Not(a) => format!("not {}", child(a, 2, extra_parens)),
            // Right operands one level up: `a and (b and c)` keeps its parentheses.
            Tree::And(a, b) => {
                let left = child(a, 1, extra_parens);
                format!("{left} and {}", child(b, 2, extra_parens))
            }
            Tree::Or(a, b) => {
                let left = child(a, 0, extra_parens);
                format!("{left} or {}", child(b, 1, extra_parens))
            }
        }
    }
}

struct Lcg(u64);

impl Lcg {
    fn below(&mut self, n: u64) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 33) % n
    }
}

fn random_tree(rng: &mut Lcg, depth: u32) -> Tree {
    if depth == 0 || rng.below(4) == 0 {
        return Tree::Atom(rng.below(ATOMS.len() as u64) as usize);
    }
    match rng.below(3) {
        0 => Tree::Not(Box::new(random_tree(rng, depth - 1))),
        1 => Tree::And(
            Box::new(random_tree(rng, depth - 1)),
            Box::new(random_tree(rng, depth - 1)),
        ),
        _ => Tree::Or(
            Box::new(random_tree(rng, depth - 1)),
            Box::new(random_tree(rng, depth - 1)),
        ),
    }
}

#[test]
fn precedence_is_pythons_against_a_naive_evaluation() {
    let r = record("chr1", 100, "chr1", 5000, "UU", 30);
    for (i, (atom, value)) in ATOMS.iter().enumerate() {
        assert_eq!(select(atom, &r), *value, "atom {i}");
    }
    let mut rng = Lcg(11);
    let mut extra_rng = Lcg(5);
    for _ in 0..500 {
        let tree = random_tree(&mut rng, 5);
        let text = tree.render(&mut || extra_rng.below(8) == 0);
        assert_eq!(select(&text, &r), tree.evaluate(), "{text}");
    }
    // The classic cases: not > and > or.
    assert!(select("True or True and False", &r));
    assert!(!select("(True or True) and False", &r));
    assert!(select("not False and True", &r));
    assert!(!select("not (False or True)", &r));
    assert!(select("not False or False", &r));
    assert!(select("not pos1 == 5", &r));
}

#[test]
fn parse_errors_say_where_and_what() {
    let cases = [
        (
            "pair_type = 'UU'",
            "at character 11: unexpected '=': use '=='",
        ),
        ("pair_type == ", "at character 14: expected a value"),
        (
            "(pos1 < 5",
            "at character 10: expected ')' to close the '(' at character 1, found the end",
        ),
        ("pos1 < 5)", "at character 9: expected an operator"),
        (
            "mapq3 > 5",
            "at character 1: unknown column 'mapq3' (the header's columns: readID chrom1",
        ),
        (
            "mapq1 == '30'",
            "at character 7: cannot compare column 'mapq1' (an integer) with the string \"30\"",
        ),
        (
            "chrom1 > 5",
            "at character 8: cannot compare column 'chrom1' (text) with the number 5",
        ),
        (
            "pair_type in ('UU', 5)",
            "cannot compare column 'pair_type' (text) with the number 5",
        ),
        (
            "chrom1",
            "at character 1: the selection must be a condition (true or false), found column 'chrom1' (text)",
        ),
        (
            "pos1 and True",
            "at character 1: 'and' takes conditions (true or false), found column 'pos1' (an integer)",
        ),
        ("not chrom1", "'not' takes conditions"),
        (
            "regex_match(chrom1, 'chr.')",
            "regex_match is not supported",
        ),
        ("len(chrom1) > 3", "unknown function 'len'"),
        (
            "chrom1 + 'x' == 'y'",
            "'+' takes a number, found column 'chrom1' (text)",
        ),
        (
            "chrom1 == 'chr1",
            "at character 11: a string that is not closed",
        ),
        (
            "csv_match(chrom1, chrom2)",
            "csv_match() takes a string (in quotes) as its second argument",
        ),
        ("abs(chrom1) > 1", "abs() takes a number"),
        ("COLS[10] == 'x'", "COLS[10]: the header has 10 columns"),
        ("('UU', 'RU')", "a tuple or list is only allowed after 'in'"),
        ("pos1 == 99999999999999999999", "is not a 64-bit integer"),
        ("pos1 < 5 and", "at character 13: expected a value"),
        ("chrom1 == 'a' && pos1 > 3", "unexpected '&': use 'and'"),
    ];
    for (expression, expected) in cases {
        let error = parse_error(expression);
        assert!(
            error.starts_with(&format!("selection '{expression}': ")),
            "{error}"
        );
        assert!(error.contains(expected), "{expression}: {error}");
    }
}

#[test]
fn bad_fields_are_record_errors() {
    let selection = Selection::parse("mapq1 > 5", &columns()).unwrap();
    let line = PairRecord::from_line(b"r\tc\t1\tc\t2\t+\t-\tUU\tNA\t3", 1);
    let error = selection.matches(&line).unwrap_err();
    assert_eq!(error, "column 'mapq1': 'NA' is not an integer");
    let short = PairRecord::from_line(b"r\tc\t1\tc\t2\t+\t-\tUU", 1);
    assert!(
        selection
            .matches(&short)
            .unwrap_err()
            .contains("no field for column 'mapq1'")
    );
    let spaced = PairRecord::from_line(b"r\tc\t1\tc\t2\t+\t-\tUU\t +7 \t3", 1);
    assert!(selection.matches(&spaced).unwrap());
    let zero = Selection::parse("pos1 / (pos2 - 2) > 1", &columns()).unwrap();
    assert!(
        zero.matches(&line)
            .unwrap_err()
            .contains("division by zero")
    );
}

#[test]
fn column_types_follow_pairtools_and_casts() {
    assert_eq!(default_column_type("pos1"), ColumnType::Integer);
    assert_eq!(default_column_type("mapq2"), ColumnType::Integer);
    assert_eq!(default_column_type("read_len1"), ColumnType::Integer);
    assert_eq!(
        default_column_type("same_side_algn_count2"),
        ColumnType::Integer
    );
    assert_eq!(default_column_type("mapq"), ColumnType::Text);
    assert_eq!(default_column_type("cigar1"), ColumnType::Text);
    assert_eq!(default_column_type("readID"), ColumnType::Text);
    let r = record("chr1", 100, "chr1", 5000, "UU", 30);
    // Read as text, mapq1 compares with strings (pairtools' `-t mapq1 str`).
    let as_text = Selection::parse_with_types(
        "mapq1 == '30'",
        &columns(),
        &[("mapq1".into(), ColumnType::Text)],
    )
    .unwrap();
    assert!(as_text.matches(&r).unwrap());
    let as_float = Selection::parse_with_types(
        "mapq1 / 4 == 7.5",
        &columns(),
        &[("mapq1".into(), ColumnType::Float)],
    )
    .unwrap();
    assert!(as_float.matches(&r).unwrap());
    assert_eq!(as_float.expression(), "mapq1 / 4 == 7.5");
}

#[test]
fn strings_take_python_escapes() {
    let line = PairRecord::from_line(b"r\\x\tc'1\t1\tc\"2\t2\t+\t-\tUU\t1\t2", 1);
    assert!(select(r#"chrom1 == 'c\'1' and chrom2 == "c\"2""#, &line));
    assert!(select(r"readID == 'r\\x'", &line));
    assert!(select(r"readID == r'r\x'", &line));
    assert!(select(r#"readID == "r\x""#, &line)); // unknown escapes keep their backslash
}
