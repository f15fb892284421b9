//! Syntax of flow-profile expressions beyond what exmex checks by itself: numbers may be
//! written in e-notation (`1e-3`, `2.5E+2`), and a name called as a function must be one
//! of exmex's functions (anything else is refused with the list, not exmex's internal
//! message).
use exmex::{FloatOpsFactory, MakeOperators, MatchLiteral};

/// Numeric literals of profile expressions: `digits[.digits][(e|E)[+|-]digits]`, or a
/// leading `.`; exmex's default matcher stops before an exponent, so `1e-3` would read as
/// `1`, Euler's `e`, `-3`.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct ScientificNumber;

impl MatchLiteral for ScientificNumber {
    fn is_literal(text: &str) -> Option<&str> {
        let bytes = text.as_bytes();
        let digits_from = |start: usize| {
            start
                + bytes[start..]
                    .iter()
                    .take_while(|b| b.is_ascii_digit())
                    .count()
        };
        let mut end = digits_from(0);
        let mut n_digits = end;
        if bytes.get(end) == Some(&b'.') {
            let after = digits_from(end + 1);
            n_digits += after - end - 1;
            end = after;
        }
        if n_digits == 0 {
            return None;
        }
        if matches!(bytes.get(end), Some(b'e' | b'E')) {
            let sign = usize::from(matches!(bytes.get(end + 1), Some(b'+' | b'-')));
            let exponent_end = digits_from(end + 1 + sign);
            if exponent_end > end + 1 + sign {
                end = exponent_end;
            }
        }
        Some(&text[..end])
    }
}

/// Names exmex accepts as functions (`sin(...)`, `atan2(y, x)`, ...), in its order.
pub fn function_names() -> Vec<&'static str> {
    FloatOpsFactory::<f64>::make()
        .iter()
        .filter(|op| {
            (op.has_unary() || op.has_bin()) && op.repr().chars().all(char::is_alphanumeric)
        })
        .map(|op| op.repr())
        .collect()
}

/// Refuses a name followed by `(` that is not one of [`function_names`], e.g. `SIN(y)`.
pub fn check_function_names(expr: &str) -> Result<(), String> {
    let known = function_names();
    let mut rest = expr;
    while let Some(c) = rest.chars().next() {
        if let Some(number) = ScientificNumber::is_literal(rest) {
            rest = &rest[number.len()..];
        } else if c.is_alphabetic() || c == '_' {
            let len = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                .unwrap_or(rest.len());
            let name = &rest[..len];
            rest = &rest[len..];
            if rest.trim_start().starts_with('(') && !known.contains(&name) {
                return Err(format!(
                    "unknown function `{name}`; the known functions are {} (names are case-sensitive)",
                    known.join(", ")
                ));
            }
        } else {
            rest = &rest[c.len_utf8()..];
        }
    }
    Ok(())
}

/// Where an expression that exmex refused breaks the grammar of profiles, as `at character
/// N (1-based): what is wrong`, or `None` when this scan finds nothing (exmex's own message
/// is then the best there is). Called only after exmex failed, so it never refuses what
/// exmex accepts: operands (numbers, names, calls `f(...)`, parenthesised expressions)
/// alternate with the binary operators `+ - * / ^`, a sign may precede an operand, commas
/// separate a call's arguments, and parentheses pair up.
pub fn locate_syntax_error(expr: &str) -> Option<String> {
    let chars: Vec<(usize, char)> = expr.char_indices().collect();
    let position = |byte: usize| expr[..byte].chars().count() + 1;
    let at = |byte: usize, what: String| Some(format!("at character {}: {what}", position(byte)));
    // Byte offsets of the open parentheses, and whether each opens a call (commas allowed).
    let mut open: Vec<(usize, bool)> = Vec::new();
    let mut want_operand = true;
    let mut k = 0;
    while k < chars.len() {
        let (byte, c) = chars[k];
        let rest = &expr[byte..];
        if c.is_whitespace() {
            k += 1;
            continue;
        }
        if want_operand {
            if let Some(number) = ScientificNumber::is_literal(rest) {
                k += number.chars().count();
                want_operand = false;
            } else if c.is_alphabetic() || c == '_' {
                let len = rest
                    .find(|c: char| !(c.is_alphanumeric() || c == '_'))
                    .unwrap_or(rest.len());
                k += rest[..len].chars().count();
                let after = rest[len..].trim_start();
                if after.starts_with('(') {
                    let skip = rest[len..].len() - after.len();
                    open.push((byte + len + skip, true));
                    k += rest[len..len + skip].chars().count() + 1;
                } else {
                    want_operand = false;
                }
            } else if c == '(' {
                open.push((byte, false));
                k += 1;
            } else if c == '-' || c == '+' {
                k += 1;
            } else {
                return at(byte, format!("`{c}` where a number, a name or `(` belongs"));
            }
        } else {
            match c {
                '+' | '-' | '*' | '/' | '^' => want_operand = true,
                ')' => {
                    if open.pop().is_none() {
                        return at(byte, "`)` closes no `(`".into());
                    }
                }
                ',' if open.last().is_some_and(|&(_, call)| call) => want_operand = true,
                _ => {
                    return at(
                        byte,
                        format!("`{c}` where an operator (+ - * / ^) or `)` belongs"),
                    )
                }
            }
            k += 1;
        }
    }
    if let Some(&(byte, _)) = open.last() {
        return at(byte, "this `(` is never closed".into());
    }
    if want_operand {
        return Some(format!(
            "at character {}: the expression ends where a number, a name or `(` belongs",
            expr.chars().count() + 1
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn syntax_errors_are_located() {
        for (expr, expected) in [
            (
                "0.1*sin(2*pi*y/L",
                "at character 8: this `(` is never closed",
            ),
            ("0.1*sin(2*pi*y/L))", "at character 18: `)` closes no `(`"),
            (
                "0.1*sin(2*pi*y/L) y",
                "at character 19: `y` where an operator",
            ),
            ("0.1*sin(2*pi*y/L)*", "at character 19: the expression ends"),
            (
                "0.1**y",
                "at character 5: `*` where a number, a name or `(` belongs",
            ),
            ("(y, L)", "at character 3: `,` where an operator"),
        ] {
            let message = locate_syntax_error(expr).unwrap_or_default();
            assert!(message.contains(expected), "{expr}: {message}");
        }
        for good in [
            "0.1*sin(2*pi*y/L)^3",
            "-1e-3*cos (y)",
            "atan2(y, L)",
            "e*y",
            "(-(y))",
        ] {
            assert_eq!(locate_syntax_error(good), None, "{good}");
        }
    }

    #[test]
    fn literals_include_exponents() {
        for (text, literal) in [
            ("1e-3*y", Some("1e-3")),
            ("2.5E+2)", Some("2.5E+2")),
            ("1e3", Some("1e3")),
            (".5*y", Some(".5")),
            ("1.", Some("1.")),
            ("2*e", Some("2")),
            ("2e", Some("2")),
            ("3e-y", Some("3")),
            ("e", None),
            (".", None),
            ("y", None),
        ] {
            assert_eq!(ScientificNumber::is_literal(text), literal, "{text}");
        }
    }

    #[test]
    fn unknown_function_is_named_with_the_known_ones() {
        let message = check_function_names("0.1*SIN(2*pi*y/L)").unwrap_err();
        assert!(
            message.contains("unknown function `SIN`")
                && message.contains("sin, cos")
                && message.contains("exp"),
            "{message}"
        );
        assert!(check_function_names("0.1 * foo (y)").is_err());
        for good in ["0.1*sin(2*pi*y/L)^3", "1e-3*cos (y)", "atan2(y, L)", "e*y"] {
            assert_eq!(check_function_names(good), Ok(()), "{good}");
        }
    }
}
