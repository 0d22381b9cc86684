//! The condition's tokens and its recursive-descent parser, with the type checks.

use super::tree::{Arithmetic, ColumnType, Comparison, Node, Number, Type, default_column_type};
use crate::error::{Error, Result};

/// Parse `expression` into a condition over `columns` (see the module docs of
/// [`super`] for the syntax), checking its types.
pub(super) fn parse(
    expression: &str,
    columns: &[String],
    types: &[(String, ColumnType)],
) -> Result<Node> {
    let tokens = tokenize(expression)?;
    let mut parser = Parser {
        expression,
        tokens,
        next: 0,
        columns,
        types,
    };
    let root = parser.condition()?;
    let end = parser.peek();
    if end.kind != TokenKind::End {
        return Err(parser.error(
            end.start,
            &format!(
                "expected an operator ('and', 'or', a comparison) or the end, found {}",
                end.kind.describe()
            ),
        ));
    }
    if root.ty != Type::Bool {
        return Err(parser.error(
            root.start,
            &format!(
                "the selection must be a condition (true or false), found {}",
                root.description
            ),
        ));
    }
    Ok(root.node)
}

#[derive(Clone, Debug, PartialEq)]
enum TokenKind {
    Name(String),
    Text(Vec<u8>),
    Int(i64),
    Float(f64),
    Symbol(&'static str),
    End,
}

impl TokenKind {
    fn describe(&self) -> String {
        match self {
            TokenKind::Name(name) => format!("'{name}'"),
            TokenKind::Text(text) => format!("the string \"{}\"", String::from_utf8_lossy(text)),
            TokenKind::Int(i) => format!("the number {i}"),
            TokenKind::Float(x) => format!("the number {x}"),
            TokenKind::Symbol(s) => format!("'{s}'"),
            TokenKind::End => "the end".into(),
        }
    }
}

#[derive(Clone, Debug)]
struct Token {
    kind: TokenKind,
    /// Byte offset in the expression.
    start: usize,
}

/// The symbols, the longer before their prefixes.
const SYMBOLS: [&str; 17] = [
    "==", "!=", "<=", ">=", "//", "<", ">", "(", ")", "[", "]", ",", "+", "-", "*", "/", "%",
];

/// The 1-based character position of byte offset `at` in `expression`.
fn char_position(expression: &str, at: usize) -> usize {
    expression[..at.min(expression.len())].chars().count() + 1
}

fn syntax_error(expression: &str, at: usize, message: &str) -> Error {
    Error::Argument(format!(
        "selection '{expression}': at character {}: {message}",
        char_position(expression, at)
    ))
}

fn tokenize(expression: &str) -> Result<Vec<Token>> {
    let bytes = expression.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let raw_prefix = matches!(c, b'r' | b'R') && matches!(bytes.get(i + 1), Some(b'"' | b'\''));
        if c == b'"' || c == b'\'' || raw_prefix {
            let raw = raw_prefix;
            if raw {
                i += 1;
            }
            let quote = bytes[i];
            i += 1;
            let mut text = Vec::new();
            loop {
                let Some(&b) = bytes.get(i) else {
                    return Err(syntax_error(
                        expression,
                        start,
                        "a string that is not closed",
                    ));
                };
                i += 1;
                if b == quote {
                    break;
                }
                if b == b'\\' && i < bytes.len() {
                    let escaped = bytes[i];
                    i += 1;
                    if raw {
                        text.extend_from_slice(&[b'\\', escaped]);
                        continue;
                    }
                    match escaped {
                        b'\\' | b'\'' | b'"' => text.push(escaped),
                        b'n' => text.push(b'\n'),
                        b't' => text.push(b'\t'),
                        b'r' => text.push(b'\r'),
                        b'0' => text.push(0),
                        _ => text.extend_from_slice(&[b'\\', escaped]),
                    }
                } else {
                    text.push(b);
                }
            }
            tokens.push(Token {
                kind: TokenKind::Text(text),
                start,
            });
        } else if c.is_ascii_digit()
            || (c == b'.' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let digits = |i: &mut usize| {
                while *i < bytes.len() && (bytes[*i].is_ascii_digit() || bytes[*i] == b'_') {
                    *i += 1;
                }
            };
            digits(&mut i);
            let mut float = false;
            if bytes.get(i) == Some(&b'.') {
                float = true;
                i += 1;
                digits(&mut i);
            }
            if matches!(bytes.get(i), Some(b'e' | b'E')) {
                let mut j = i + 1;
                if matches!(bytes.get(j), Some(b'+' | b'-')) {
                    j += 1;
                }
                if bytes.get(j).is_some_and(u8::is_ascii_digit) {
                    float = true;
                    i = j;
                    digits(&mut i);
                }
            }
            let literal = expression[start..i].replace('_', "");
            let kind = if float {
                TokenKind::Float(literal.parse().map_err(|_| {
                    syntax_error(expression, start, &format!("'{literal}' is not a number"))
                })?)
            } else {
                TokenKind::Int(literal.parse().map_err(|_| {
                    syntax_error(
                        expression,
                        start,
                        &format!("'{literal}' is not a 64-bit integer"),
                    )
                })?)
            };
            tokens.push(Token { kind, start });
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            tokens.push(Token {
                kind: TokenKind::Name(expression[start..i].to_string()),
                start,
            });
        } else if let Some(symbol) = SYMBOLS.iter().find(|s| expression[i..].starts_with(**s)) {
            i += symbol.len();
            tokens.push(Token {
                kind: TokenKind::Symbol(symbol),
                start,
            });
        } else {
            let found = expression[i..].chars().next().unwrap_or('?');
            let hint = match c {
                b'=' => ": use '==' to compare",
                b'&' => ": use 'and'",
                b'|' => ": use 'or'",
                b'!' => ": use 'not' or '!='",
                _ => "",
            };
            return Err(syntax_error(
                expression,
                start,
                &format!("unexpected '{found}'{hint}"),
            ));
        }
    }
    tokens.push(Token {
        kind: TokenKind::End,
        start: bytes.len(),
    });
    Ok(tokens)
}

/// A parsed node with its type, where it starts and how to name it in errors.
struct Typed {
    node: Node,
    ty: Type,
    start: usize,
    description: String,
}

/// Recursive descent over the tokens, one method per precedence level.
struct Parser<'a> {
    expression: &'a str,
    tokens: Vec<Token>,
    next: usize,
    columns: &'a [String],
    types: &'a [(String, ColumnType)],
}

const KEYWORDS: [&str; 5] = ["and", "or", "not", "in", "is"];

impl Parser<'_> {
    fn peek(&self) -> &Token {
        &self.tokens[self.next]
    }

    fn advance(&mut self) -> Token {
        let token = self.tokens[self.next].clone();
        if self.next + 1 < self.tokens.len() {
            self.next += 1;
        }
        token
    }

    fn at_symbol(&self, symbol: &'static str) -> bool {
        self.peek().kind == TokenKind::Symbol(symbol)
    }

    fn at_name(&self, name: &str) -> bool {
        matches!(&self.peek().kind, TokenKind::Name(n) if n == name)
    }

    fn error(&self, at: usize, message: &str) -> Error {
        syntax_error(self.expression, at, message)
    }

    fn expect_symbol(&mut self, symbol: &'static str, context: &str) -> Result<()> {
        if self.at_symbol(symbol) {
            self.advance();
            Ok(())
        } else {
            let token = self.peek();
            Err(self.error(
                token.start,
                &format!(
                    "expected '{symbol}'{context}, found {}",
                    token.kind.describe()
                ),
            ))
        }
    }

    /// A condition operand of `and`, `or`, `not`.
    fn require_condition(&self, operand: &Typed, operator: &str) -> Result<()> {
        if operand.ty == Type::Bool {
            Ok(())
        } else {
            Err(self.error(
                operand.start,
                &format!(
                    "'{operator}' takes conditions (true or false), found {}",
                    operand.description
                ),
            ))
        }
    }

    fn require(&self, operand: &Typed, ty: Type, context: &str) -> Result<()> {
        if operand.ty == ty {
            Ok(())
        } else {
            let what = match ty {
                Type::Number => "a number",
                Type::Text => "text",
                Type::Bool => "a condition",
                Type::List => "a tuple or list",
            };
            Err(self.error(
                operand.start,
                &format!("{context} takes {what}, found {}", operand.description),
            ))
        }
    }

    fn condition(&mut self) -> Result<Typed> {
        let mut left = self.and_condition()?;
        while self.at_name("or") {
            self.advance();
            let right = self.and_condition()?;
            self.require_condition(&left, "or")?;
            self.require_condition(&right, "or")?;
            left = Typed {
                node: Node::Or(Box::new(left.node), Box::new(right.node)),
                ty: Type::Bool,
                start: left.start,
                description: "a condition".into(),
            };
        }
        Ok(left)
    }

    fn and_condition(&mut self) -> Result<Typed> {
        let mut left = self.not_condition()?;
        while self.at_name("and") {
            self.advance();
            let right = self.not_condition()?;
            self.require_condition(&left, "and")?;
            self.require_condition(&right, "and")?;
            left = Typed {
                node: Node::And(Box::new(left.node), Box::new(right.node)),
                ty: Type::Bool,
                start: left.start,
                description: "a condition".into(),
            };
        }
        Ok(left)
    }

    fn not_condition(&mut self) -> Result<Typed> {
        if self.at_name("not") {
            let start = self.advance().start;
            let operand = self.not_condition()?;
            self.require_condition(&operand, "not")?;
            return Ok(Typed {
                node: Node::Not(Box::new(operand.node)),
                ty: Type::Bool,
                start,
                description: "a condition".into(),
            });
        }
        self.comparison()
    }

    fn comparison_operator(&mut self) -> Option<(Comparison, usize)> {
        let token = self.peek().clone();
        let op = match &token.kind {
            TokenKind::Symbol("==") => Comparison::Equal,
            TokenKind::Symbol("!=") => Comparison::NotEqual,
            TokenKind::Symbol("<") => Comparison::Less,
            TokenKind::Symbol("<=") => Comparison::LessEqual,
            TokenKind::Symbol(">") => Comparison::Greater,
            TokenKind::Symbol(">=") => Comparison::GreaterEqual,
            TokenKind::Name(n) if n == "in" => Comparison::In,
            TokenKind::Name(n)
                if n == "not"
                    && matches!(&self.tokens[self.next + 1].kind, TokenKind::Name(m) if m == "in") =>
            {
                self.advance();
                Comparison::NotIn
            }
            _ => return None,
        };
        self.advance();
        Some((op, token.start))
    }

    fn comparison(&mut self) -> Result<Typed> {
        let first = self.sum()?;
        let mut links = Vec::new();
        let mut left_type = first.ty;
        let mut left_description = first.description.clone();
        while let Some((op, at)) = self.comparison_operator() {
            let right = self.sum()?;
            let compatible = match op {
                Comparison::In | Comparison::NotIn => match right.ty {
                    Type::List => {
                        // Every element must compare with the left side.
                        if let Node::List(items) = &right.node {
                            for item in items {
                                let item_type = node_type(item);
                                if item_type != left_type {
                                    return Err(self.mismatch(
                                        at,
                                        &left_description,
                                        &describe_node(item),
                                    ));
                                }
                            }
                        }
                        true
                    }
                    Type::Text => left_type == Type::Text,
                    _ => false,
                },
                _ => left_type == right.ty && left_type != Type::List,
            };
            if !compatible {
                return Err(self.mismatch(at, &left_description, &right.description));
            }
            left_type = right.ty;
            left_description = right.description.clone();
            links.push((op, right.node));
        }
        if links.is_empty() {
            if first.ty == Type::List {
                return Err(self.error(
                    first.start,
                    "a tuple or list is only allowed after 'in' or 'not in'",
                ));
            }
            return Ok(first);
        }
        Ok(Typed {
            node: Node::Compare(Box::new(first.node), links),
            ty: Type::Bool,
            start: first.start,
            description: "a condition".into(),
        })
    }

    fn mismatch(&self, at: usize, left: &str, right: &str) -> Error {
        self.error(
            at,
            &format!(
                "cannot compare {left} with {right} (numbers compare with numbers, text with text)"
            ),
        )
    }

    fn sum(&mut self) -> Result<Typed> {
        let mut left = self.term()?;
        loop {
            let op = if self.at_symbol("+") {
                Arithmetic::Add
            } else if self.at_symbol("-") {
                Arithmetic::Subtract
            } else {
                return Ok(left);
            };
            left = self.arithmetic(left, op, Parser::term)?;
        }
    }

    fn term(&mut self) -> Result<Typed> {
        let mut left = self.factor()?;
        loop {
            let op = if self.at_symbol("*") {
                Arithmetic::Multiply
            } else if self.at_symbol("/") {
                Arithmetic::Divide
            } else if self.at_symbol("//") {
                Arithmetic::FloorDivide
            } else if self.at_symbol("%") {
                Arithmetic::Remainder
            } else {
                return Ok(left);
            };
            left = self.arithmetic(left, op, Parser::factor)?;
        }
    }

    fn arithmetic(
        &mut self,
        left: Typed,
        op: Arithmetic,
        operand: fn(&mut Self) -> Result<Typed>,
    ) -> Result<Typed> {
        self.advance();
        let right = operand(self)?;
        let context = format!("'{}'", op.symbol());
        self.require(&left, Type::Number, &context)?;
        self.require(&right, Type::Number, &context)?;
        Ok(Typed {
            node: Node::Arithmetic(op, Box::new(left.node), Box::new(right.node)),
            ty: Type::Number,
            start: left.start,
            description: "a number".into(),
        })
    }

    fn factor(&mut self) -> Result<Typed> {
        if self.at_symbol("-") || self.at_symbol("+") {
            let token = self.advance();
            let operand = self.factor()?;
            let symbol = if token.kind == TokenKind::Symbol("-") {
                "-"
            } else {
                "+"
            };
            self.require(&operand, Type::Number, &format!("unary '{symbol}'"))?;
            let node = match (symbol, operand.node) {
                ("+", node) => node,
                (_, Node::Number(Number::Int(i))) => Node::Number(Number::Int(-i)),
                (_, Node::Number(Number::Float(x))) => Node::Number(Number::Float(-x)),
                (_, node) => Node::Negate(Box::new(node)),
            };
            return Ok(Typed {
                description: describe_node(&node),
                node,
                ty: Type::Number,
                start: token.start,
            });
        }
        self.atom()
    }

    fn column(&self, name: &str, at: usize) -> Result<Typed> {
        let index = self.columns.iter().position(|c| c == name).ok_or_else(|| {
            self.error(
                at,
                &format!(
                    "unknown column '{name}' (the header's columns: {})",
                    self.columns.join(" ")
                ),
            )
        })?;
        let column_type = self
            .types
            .iter()
            .rev()
            .find(|(c, _)| c == name)
            .map_or_else(|| default_column_type(name), |(_, t)| *t);
        let node = Node::Column {
            index,
            name: name.to_string(),
            column_type,
        };
        Ok(Typed {
            description: describe_node(&node),
            ty: node_type(&node),
            node,
            start: at,
        })
    }

    fn atom(&mut self) -> Result<Typed> {
        let token = self.advance();
        let start = token.start;
        let literal = |node: Node| {
            Ok(Typed {
                description: describe_node(&node),
                ty: node_type(&node),
                node,
                start,
            })
        };
        match token.kind {
            TokenKind::Int(i) => literal(Node::Number(Number::Int(i))),
            TokenKind::Float(x) => literal(Node::Number(Number::Float(x))),
            TokenKind::Text(text) => literal(Node::Text(text)),
            TokenKind::Symbol("(") => self.parenthesized(start),
            TokenKind::Symbol("[") => {
                let items = self.items("]", start)?;
                literal(Node::List(items))
            }
            TokenKind::Name(name) => match name.as_str() {
                "True" => literal(Node::Bool(true)),
                "False" => literal(Node::Bool(false)),
                "COLS" => self.cols(start),
                "abs" | "csv_match" | "wildcard_match" => self.call(&name, start),
                "regex_match" => Err(self.error(
                    start,
                    "regex_match is not supported (no regular expressions here): use \
                     wildcard_match(column, \"pattern\") or csv_match(column, \"a,b\")",
                )),
                _ if KEYWORDS.contains(&name.as_str()) => {
                    Err(self.error(start, &format!("expected a value before '{name}'")))
                }
                _ if self.at_symbol("(") => Err(self.error(
                    start,
                    &format!(
                        "unknown function '{name}' (the functions are abs, csv_match and \
                         wildcard_match)"
                    ),
                )),
                _ => self.column(&name, start),
            },
            kind => Err(self.error(
                start,
                &format!(
                    "expected a value (a column, a number, a string, '(' or 'not'), found {}",
                    kind.describe()
                ),
            )),
        }
    }

    /// After `(`: a grouped expression, or a tuple when a comma follows its first element.
    fn parenthesized(&mut self, start: usize) -> Result<Typed> {
        if self.at_symbol(")") {
            self.advance();
            return Ok(Typed {
                node: Node::List(Vec::new()),
                ty: Type::List,
                start,
                description: "a tuple".into(),
            });
        }
        let inner = self.condition()?;
        if self.at_symbol(",") {
            self.advance();
            let mut items = vec![self.item(inner)?];
            items.extend(self.items(")", start)?);
            return Ok(Typed {
                node: Node::List(items),
                ty: Type::List,
                start,
                description: "a tuple".into(),
            });
        }
        self.expect_symbol(
            ")",
            &format!(
                " to close the '(' at character {}",
                char_position(self.expression, start)
            ),
        )?;
        Ok(Typed { start, ..inner })
    }

    /// A tuple or list element: a number or text.
    fn item(&self, item: Typed) -> Result<Node> {
        if matches!(item.ty, Type::Number | Type::Text) {
            Ok(item.node)
        } else {
            Err(self.error(
                item.start,
                &format!(
                    "a tuple or list holds numbers or text, found {}",
                    item.description
                ),
            ))
        }
    }

    /// Elements up to the closing `close` (a trailing comma allowed).
    fn items(&mut self, close: &'static str, start: usize) -> Result<Vec<Node>> {
        let mut items = Vec::new();
        loop {
            if self.at_symbol(close) {
                self.advance();
                return Ok(items);
            }
            let item = self.sum()?;
            items.push(self.item(item)?);
            if self.at_symbol(",") {
                self.advance();
            } else {
                let context = format!(
                    " or ',' in the list opened at character {}",
                    char_position(self.expression, start)
                );
                self.expect_symbol(close, &context)?;
                return Ok(items);
            }
        }
    }

    /// `COLS[i]`: field `i` as text.
    fn cols(&mut self, start: usize) -> Result<Typed> {
        self.expect_symbol("[", " after COLS")?;
        let token = self.advance();
        let TokenKind::Int(index) = token.kind else {
            return Err(self.error(
                token.start,
                &format!(
                    "expected a field number in COLS[...], found {}",
                    token.kind.describe()
                ),
            ));
        };
        if index < 0 || index as usize >= self.columns.len().max(1) {
            return Err(self.error(
                token.start,
                &format!(
                    "COLS[{index}]: the header has {} columns (COLS[0] to COLS[{}])",
                    self.columns.len(),
                    self.columns.len().saturating_sub(1)
                ),
            ));
        }
        self.expect_symbol("]", " after the field number")?;
        let node = Node::Column {
            index: index as usize,
            name: format!("COLS[{index}]"),
            column_type: ColumnType::Text,
        };
        Ok(Typed {
            description: describe_node(&node),
            ty: Type::Text,
            node,
            start,
        })
    }

    fn call(&mut self, name: &str, start: usize) -> Result<Typed> {
        self.expect_symbol("(", &format!(" after '{name}'"))?;
        let argument = self.sum()?;
        let node = if name == "abs" {
            self.require(&argument, Type::Number, "abs()")?;
            Node::Abs(Box::new(argument.node))
        } else {
            self.require(&argument, Type::Text, &format!("{name}()"))?;
            self.expect_symbol(",", &format!(" between the arguments of {name}()"))?;
            let token = self.advance();
            let TokenKind::Text(pattern) = token.kind else {
                return Err(self.error(
                    token.start,
                    &format!(
                        "{name}() takes a string (in quotes) as its second argument, found {}",
                        token.kind.describe()
                    ),
                ));
            };
            if name == "csv_match" {
                let values = pattern.split(|&b| b == b',').map(<[u8]>::to_vec).collect();
                Node::CsvMatch(Box::new(argument.node), values)
            } else {
                Node::WildcardMatch(Box::new(argument.node), pattern)
            }
        };
        self.expect_symbol(")", &format!(" to close {name}()"))?;
        Ok(Typed {
            ty: node_type(&node),
            description: describe_node(&node),
            node,
            start,
        })
    }
}

fn node_type(node: &Node) -> Type {
    match node {
        Node::Bool(_)
        | Node::Not(_)
        | Node::And(..)
        | Node::Or(..)
        | Node::Compare(..)
        | Node::CsvMatch(..)
        | Node::WildcardMatch(..) => Type::Bool,
        Node::Number(_) | Node::Arithmetic(..) | Node::Negate(_) | Node::Abs(_) => Type::Number,
        Node::Text(_) => Type::Text,
        Node::List(_) => Type::List,
        Node::Column { column_type, .. } => match column_type {
            ColumnType::Text => Type::Text,
            ColumnType::Integer | ColumnType::Float => Type::Number,
        },
    }
}

/// How an operand is named in errors.
fn describe_node(node: &Node) -> String {
    match node {
        Node::Column {
            name, column_type, ..
        } => match column_type {
            ColumnType::Text => format!("column '{name}' (text)"),
            ColumnType::Integer => format!("column '{name}' (an integer)"),
            ColumnType::Float => format!("column '{name}' (a number)"),
        },
        Node::Number(n) => format!("the number {n}"),
        Node::Text(t) => format!("the string \"{}\"", String::from_utf8_lossy(t)),
        Node::Bool(b) => if *b { "True" } else { "False" }.to_string(),
        Node::List(_) => "a tuple or list".into(),
        other => match node_type(other) {
            Type::Bool => "a condition".into(),
            Type::Number => "a number".into(),
            Type::Text => "text".into(),
            Type::List => "a tuple or list".into(),
        },
    }
}
