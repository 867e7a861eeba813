//! Recursive-descent parser with Adams precedence and static shape (scalar/vector) checking.
//!
//! Grammar (lowest to highest precedence):
//!
//! ```text
//! expr    := term (('+' | '-') term)*
//! term    := unary (('*' | '/' | '%') unary)*
//! unary   := ('-' | '+') unary | power
//! power   := primary ('**' unary)?          -- right-associative; -A**-B = -(A**(-B))
//! primary := number | constant | name '(' args ')' | 'IF' '(' expr ':' expr ',' expr ',' expr ')'
//!          | 'USER' '(' args ')' | '(' expr ')' | '[' expr ',' expr ',' expr ']'
//! ```

use crate::ast::{BinOp, Expr};
use crate::catalog::{arity_message, Constant, Function};
use crate::error::ParseError;
use crate::lexer::{tokenize, Tok, Token};

/// Maximum depth of the expression tree. Deeper input (e.g. a sum of more than 256 terms) is
/// rejected with a [`ParseError`] instead of risking a stack overflow during evaluation.
pub const MAX_DEPTH: usize = 256;

/// Maximum nesting of parentheses, brackets, function calls and unary operators, which is
/// what drives the parser's recursion.
pub const MAX_NESTING: usize = 64;

/// Parses a function expression into a scalar-valued [`Expr`].
///
/// Errors carry the byte offset of the offending token. Unknown names are errors at the name;
/// vector operands in scalar positions are errors at the operator or argument; a vector-valued
/// whole expression is an error at offset 0.
pub fn parse(text: &str) -> Result<Expr, ParseError> {
    let tokens = tokenize(text)?;
    let mut p = Parser {
        src: text,
        tokens,
        pos: 0,
        nesting: 0,
    };
    if p.peek().tok == Tok::End {
        return Err(ParseError::new(p.peek().offset, "empty expression"));
    }
    let node = p.expr()?;
    let next = p.peek();
    if next.tok != Tok::End {
        let message = match next.tok {
            Tok::RParen | Tok::RBracket => format!("unmatched {}", next.describe(text)),
            _ => format!(
                "expected an operator or end of expression, found {}",
                next.describe(text)
            ),
        };
        return Err(ParseError::new(next.offset, message));
    }
    if node.shape == Shape::Vector {
        return Err(ParseError::new(
            node.offset,
            "the expression is a vector; a scalar is required",
        ));
    }
    Ok(node.expr)
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Shape {
    Scalar,
    Vector,
}

/// A parsed sub-expression with its static shape, tree depth and starting offset.
struct Node {
    expr: Expr,
    shape: Shape,
    depth: usize,
    offset: usize,
}

struct Parser<'a> {
    src: &'a str,
    tokens: Vec<Token>,
    pos: usize,
    nesting: usize,
}

const END: Token = Token {
    tok: Tok::End,
    offset: 0,
    len: 0,
};

impl Parser<'_> {
    fn peek(&self) -> &Token {
        // The token list always ends with End, and `pos` never moves past it.
        self.tokens
            .get(self.pos)
            .or_else(|| self.tokens.last())
            .unwrap_or(&END)
    }

    fn bump(&mut self) -> Token {
        let t = self.peek().clone();
        if t.tok != Tok::End {
            self.pos += 1;
        }
        t
    }

    fn describe_next(&self) -> String {
        self.peek().describe(self.src)
    }

    fn error_here(&self, message: impl Into<String>) -> ParseError {
        ParseError::new(self.peek().offset, message)
    }

    fn too_deep(offset: usize) -> ParseError {
        ParseError::new(
            offset,
            format!("expression is nested too deeply (more than {MAX_DEPTH} levels)"),
        )
    }

    fn node(expr: Expr, shape: Shape, depth: usize, offset: usize) -> Result<Node, ParseError> {
        if depth > MAX_DEPTH {
            return Err(Self::too_deep(offset));
        }
        Ok(Node {
            expr,
            shape,
            depth,
            offset,
        })
    }

    fn expr(&mut self) -> Result<Node, ParseError> {
        let mut lhs = self.term()?;
        loop {
            let op = match self.peek().tok {
                Tok::Plus => BinOp::Add,
                Tok::Minus => BinOp::Sub,
                _ => return Ok(lhs),
            };
            let at = self.bump().offset;
            let rhs = self.term()?;
            lhs = Self::binary(op, lhs, rhs, at)?;
        }
    }

    fn term(&mut self) -> Result<Node, ParseError> {
        let mut lhs = self.unary()?;
        loop {
            let op = match self.peek().tok {
                Tok::Star => BinOp::Mul,
                Tok::Slash => BinOp::Div,
                Tok::Percent => BinOp::Cross,
                _ => return Ok(lhs),
            };
            let at = self.bump().offset;
            let rhs = self.unary()?;
            lhs = Self::binary(op, lhs, rhs, at)?;
        }
    }

    fn unary(&mut self) -> Result<Node, ParseError> {
        let start = self.peek().offset;
        self.nesting += 1;
        if self.nesting > MAX_NESTING {
            return Err(ParseError::new(
                start,
                format!(
                    "expression is nested too deeply (more than {MAX_NESTING} levels of \
                     parentheses, calls or unary operators)"
                ),
            ));
        }
        let result = match self.peek().tok {
            Tok::Minus => {
                self.bump();
                self.unary().and_then(|operand| {
                    Self::node(
                        Expr::Neg(Box::new(operand.expr)),
                        operand.shape,
                        operand.depth + 1,
                        start,
                    )
                })
            }
            Tok::Plus => {
                self.bump();
                self.unary().map(|mut operand| {
                    operand.offset = start;
                    operand
                })
            }
            _ => self.power(),
        };
        self.nesting -= 1;
        result
    }

    fn power(&mut self) -> Result<Node, ParseError> {
        let base = self.primary()?;
        if self.peek().tok != Tok::Power {
            return Ok(base);
        }
        let at = self.bump().offset;
        let exponent = self.unary()?;
        Self::binary(BinOp::Pow, base, exponent, at)
    }

    /// Builds a binary node after checking operand shapes.
    fn binary(op: BinOp, lhs: Node, rhs: Node, at: usize) -> Result<Node, ParseError> {
        use Shape::{Scalar as S, Vector as V};
        let shape = match (op, lhs.shape, rhs.shape) {
            (BinOp::Add | BinOp::Sub, S, S) => S,
            (BinOp::Add | BinOp::Sub, V, V) => V,
            (BinOp::Add | BinOp::Sub, _, _) => {
                return Err(ParseError::new(
                    at,
                    format!(
                        "operator '{}' cannot combine a scalar and a vector",
                        op.symbol()
                    ),
                ))
            }
            (BinOp::Mul, S, S) | (BinOp::Mul, V, V) => S,
            (BinOp::Mul, _, _) => V,
            (BinOp::Div, S, S) => S,
            (BinOp::Div, V, S) => V,
            (BinOp::Div, _, V) => {
                return Err(ParseError::new(at, "cannot divide by a vector"));
            }
            (BinOp::Cross, V, V) => V,
            (BinOp::Cross, _, _) => {
                return Err(ParseError::new(
                    at,
                    "operator '%' (cross product) requires two vectors",
                ))
            }
            (BinOp::Pow, S, S) => S,
            (BinOp::Pow, _, _) => {
                return Err(ParseError::new(
                    at,
                    "operator '**' requires scalar operands",
                ));
            }
        };
        let depth = lhs.depth.max(rhs.depth) + 1;
        let offset = lhs.offset;
        Self::node(
            Expr::Binary {
                op,
                lhs: Box::new(lhs.expr),
                rhs: Box::new(rhs.expr),
            },
            shape,
            depth,
            offset,
        )
    }

    fn primary(&mut self) -> Result<Node, ParseError> {
        let token = self.peek().clone();
        match &token.tok {
            Tok::Number { value, degrees } => {
                self.bump();
                let expr = if *degrees {
                    Expr::Degrees(*value)
                } else {
                    Expr::Number(*value)
                };
                Self::node(expr, Shape::Scalar, 1, token.offset)
            }
            Tok::LParen => {
                self.bump();
                let mut inner = self.expr()?;
                self.close(Tok::RParen, "')'", "'('", token.offset)?;
                inner.offset = token.offset;
                Ok(inner)
            }
            Tok::LBracket => {
                self.bump();
                let mut items = Vec::with_capacity(3);
                loop {
                    let item = self.expr()?;
                    Self::require_scalar(&item, "a vector component")?;
                    items.push(item);
                    match self.peek().tok {
                        Tok::Comma if items.len() < 3 => {
                            self.bump();
                        }
                        Tok::RBracket if items.len() == 3 => {
                            self.bump();
                            break;
                        }
                        _ => {
                            let expected = if items.len() < 3 { "','" } else { "']'" };
                            return Err(self.error_here(format!(
                                "expected {expected} in vector '[x, y, z]' opened at offset {}, \
                                 found {}",
                                token.offset,
                                self.describe_next()
                            )));
                        }
                    }
                }
                let depth = items.iter().map(|n| n.depth).max().unwrap_or(0) + 1;
                let mut it = items.into_iter().map(|n| n.expr);
                match (it.next(), it.next(), it.next()) {
                    (Some(x), Some(y), Some(z)) => Self::node(
                        Expr::Vector(Box::new([x, y, z])),
                        Shape::Vector,
                        depth,
                        token.offset,
                    ),
                    _ => Err(ParseError::new(token.offset, "malformed vector")),
                }
            }
            Tok::Name(name) => {
                self.bump();
                self.named(name, token.offset)
            }
            Tok::End => Err(self.error_here("unexpected end of expression: expected an operand")),
            _ => Err(self.error_here(format!(
                "expected an operand (number, name, '(' or '['), found {}",
                token.describe(self.src)
            ))),
        }
    }

    /// Expects the closing token `close` of a group opened at `open_offset`.
    fn close(
        &mut self,
        close: Tok,
        close_text: &str,
        open_text: &str,
        open_offset: usize,
    ) -> Result<(), ParseError> {
        if self.peek().tok == close {
            self.bump();
            Ok(())
        } else {
            Err(self.error_here(format!(
                "expected {close_text} to close {open_text} opened at offset {open_offset}, \
                 found {}",
                self.describe_next()
            )))
        }
    }

    fn require_scalar(node: &Node, what: &str) -> Result<(), ParseError> {
        if node.shape == Shape::Vector {
            Err(ParseError::new(
                node.offset,
                format!("{what} must be a scalar, not a vector"),
            ))
        } else {
            Ok(())
        }
    }

    /// Parses what follows a name: a constant, IF, USER or a function call.
    fn named(&mut self, name: &str, at: usize) -> Result<Node, ParseError> {
        let followed_by_paren = self.peek().tok == Tok::LParen;
        if let Some(c) = Constant::from_name(name) {
            if followed_by_paren {
                return Err(ParseError::new(
                    at,
                    format!("{name} is a constant, not a function"),
                ));
            }
            return Self::node(Expr::Constant(c), Shape::Scalar, 1, at);
        }
        let known = name == "IF" || name == "USER" || Function::lookup(name).is_some();
        if !known {
            let message = if followed_by_paren {
                format!("unknown function '{name}'")
            } else {
                format!("unknown name '{name}'")
            };
            return Err(ParseError::new(at, message));
        }
        if !followed_by_paren {
            return Err(self.error_here(format!(
                "expected '(' after function name {name}, found {}",
                self.describe_next()
            )));
        }
        let open = self.bump().offset;
        if name == "IF" {
            return self.if_args(open, at);
        }
        let args = self.call_args(open, name)?;
        let depth = args.iter().map(|n| n.depth).max().unwrap_or(0) + 1;
        let exprs: Vec<Expr> = args.into_iter().map(|n| n.expr).collect();
        if name == "USER" {
            return Self::node(Expr::User(exprs), Shape::Scalar, depth, at);
        }
        let Some(func) = Function::lookup(name) else {
            return Err(ParseError::new(at, format!("unknown function '{name}'")));
        };
        let (min, max) = func.arity();
        if exprs.len() < min || exprs.len() > max {
            return Err(ParseError::new(
                at,
                arity_message(name, (min, max), exprs.len()),
            ));
        }
        Self::node(Expr::Call { func, args: exprs }, Shape::Scalar, depth, at)
    }

    /// Parses a comma-separated argument list after '(' (already consumed) up to ')'.
    fn call_args(&mut self, open: usize, name: &str) -> Result<Vec<Node>, ParseError> {
        let mut args = Vec::new();
        if self.peek().tok == Tok::RParen {
            self.bump();
            return Ok(args);
        }
        loop {
            let arg = self.expr()?;
            Self::require_scalar(&arg, &format!("argument {} of {name}", args.len() + 1))?;
            args.push(arg);
            match self.peek().tok {
                Tok::Comma => {
                    self.bump();
                }
                Tok::RParen => {
                    self.bump();
                    return Ok(args);
                }
                _ => {
                    return Err(self.error_here(format!(
                        "expected ')' to close '(' opened at offset {open}, found {}",
                        self.describe_next()
                    )))
                }
            }
        }
    }

    /// Parses `test: lt, eq, gt)` of an arithmetic IF whose '(' is at `open`.
    fn if_args(&mut self, open: usize, at: usize) -> Result<Node, ParseError> {
        let test = self.expr()?;
        Self::require_scalar(&test, "the test of IF")?;
        if self.peek().tok != Tok::Colon {
            return Err(self.error_here(format!(
                "expected ':' after the test of IF(test: lt, eq, gt), found {}",
                self.describe_next()
            )));
        }
        self.bump();
        let mut branches = Vec::with_capacity(3);
        for i in 0..3 {
            let b = self.expr()?;
            Self::require_scalar(&b, "a branch of IF")?;
            branches.push(b);
            if i < 2 {
                if self.peek().tok != Tok::Comma {
                    return Err(self.error_here(format!(
                        "expected ',' between the branches of IF(test: lt, eq, gt), found {}",
                        self.describe_next()
                    )));
                }
                self.bump();
            }
        }
        self.close(Tok::RParen, "')'", "'('", open)?;
        let depth = branches
            .iter()
            .map(|n| n.depth)
            .max()
            .unwrap_or(0)
            .max(test.depth)
            + 1;
        let mut it = branches.into_iter().map(|n| Box::new(n.expr));
        match (it.next(), it.next(), it.next()) {
            (Some(lt), Some(eq), Some(gt)) => Self::node(
                Expr::If {
                    test: Box::new(test.expr),
                    lt,
                    eq,
                    gt,
                },
                Shape::Scalar,
                depth,
                at,
            ),
            _ => Err(ParseError::new(at, "malformed IF")),
        }
    }
}
