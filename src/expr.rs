//! Expressions of position and time in scene files: prescribed boundary motion,
//! tractions and time functions ([`crate::motion`]), e.g. `"1e-3 * y * min(t / 2, 1)"`.
//!
//! The text is parsed by the `evalexpr` crate (its grammar and precedence: `-x^2` is
//! −(x²), `1e-3` is a literal) and its operator tree is compiled once into a short
//! program of `f64` operations ([`Expr`]), evaluated with a fixed-size stack: no
//! allocation, no name look-up and no dynamic typing at run time, and every number is
//! an `f64` (`1/2` is 0.5, not evalexpr's integer 0). Compiling rejects, with a message
//! the scene names the field of: a text that does not parse, a name that is not a
//! variable of the field (`x`, `y`, `z` in 3D, `t`) or the constant `pi`, an unknown
//! function, a function with the wrong number of arguments, anything that is not
//! arithmetic (comparisons, booleans, strings, assignments, `;`), and `a^b^c` without
//! parentheses (evalexpr reads it as (a^b)^c, mathematics as a^(b^c)).
//!
//! Operators: `+ - * / ^` and unary `-`. Functions: `sin cos tan asin acos atan sinh
//! cosh tanh exp ln log10 sqrt cbrt abs floor ceil` of one argument, `atan2(y, x)`,
//! `min`, `max`, `pow`, `hypot` of two (a `math::` prefix, evalexpr's spelling, is
//! accepted too).

use evalexpr::{DefaultNumericTypes, Node, Operator, Value};

/// The variables an expression may use, by slot: x, y, z, t.
pub const VARIABLES: [&str; 4] = ["x", "y", "z", "t"];
/// Slot of `t` in the values passed to [`Expr::eval`].
pub const T: usize = 3;

/// Deepest evaluation stack an expression may need (a limit on nesting, far above any
/// boundary condition's).
const MAX_DEPTH: usize = 32;

#[derive(Clone, Copy, Debug)]
enum Op {
    Const(f64),
    Var(u8),
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Neg,
    F1(fn(f64) -> f64),
    F2(fn(f64, f64) -> f64),
}

/// A compiled expression (see the module doc).
#[derive(Clone, Debug)]
pub struct Expr {
    /// The program in postfix order.
    ops: Vec<Op>,
    /// Bit v set: uses variable slot v.
    uses: u8,
    /// The text as written.
    pub text: String,
}

/// Two expressions are equal when their texts are (the program follows from the text).
impl PartialEq for Expr {
    fn eq(&self, other: &Expr) -> bool {
        self.text == other.text
    }
}

fn function1(name: &str) -> Option<fn(f64) -> f64> {
    Some(match name {
        "sin" => f64::sin,
        "cos" => f64::cos,
        "tan" => f64::tan,
        "asin" => f64::asin,
        "acos" => f64::acos,
        "atan" => f64::atan,
        "sinh" => f64::sinh,
        "cosh" => f64::cosh,
        "tanh" => f64::tanh,
        "exp" => f64::exp,
        "ln" => f64::ln,
        "log10" => f64::log10,
        "sqrt" => f64::sqrt,
        "cbrt" => f64::cbrt,
        "abs" => f64::abs,
        "floor" => f64::floor,
        "ceil" => f64::ceil,
        _ => return None,
    })
}

fn function2(name: &str) -> Option<fn(f64, f64) -> f64> {
    Some(match name {
        "atan2" => f64::atan2,
        "min" => f64::min,
        "max" => f64::max,
        "pow" => f64::powf,
        "hypot" => f64::hypot,
        _ => return None,
    })
}

impl Expr {
    /// Compile `text`, whose variables may be those of `VARIABLES` whose slot is in
    /// `allowed` (e.g. `&[0, 1, 3]` for x, y, t in 2D). The error is a sentence for the
    /// scene to prefix with the field.
    pub fn parse(text: &str, allowed: &[usize]) -> Result<Expr, String> {
        let tree = evalexpr::build_operator_tree::<DefaultNumericTypes>(text).map_err(|e| format!("the expression \"{text}\" does not parse: {e}"))?;
        let mut expr = Expr { ops: Vec::new(), uses: 0, text: text.to_string() };
        expr.compile(&tree, allowed)?;
        if expr.ops.is_empty() {
            return Err(format!("the expression \"{text}\" is empty"));
        }
        // Every operation must find its operands, and one value must remain (a check of
        // the compiled program against any tree evalexpr accepts but cannot evaluate).
        let depth = expr.depth().ok_or_else(|| format!("the expression \"{text}\" does not parse: an operator or function lacks an operand"))?;
        if depth > MAX_DEPTH {
            return Err(format!("the expression \"{text}\" nests too deeply ({depth} values at once; at most {MAX_DEPTH})"));
        }
        Ok(expr)
    }

    fn compile(&mut self, node: &Node<DefaultNumericTypes>, allowed: &[usize]) -> Result<(), String> {
        let text = self.text.clone();
        let children = node.children();
        let binary = |op: Op, this: &mut Expr| -> Result<(), String> {
            // evalexpr builds `x +` with one operand and fails only when evaluating it.
            let arity = if matches!(op, Op::Neg) { 1 } else { 2 };
            if children.len() != arity {
                return Err(format!("the expression \"{text}\" does not parse: `{}` needs {arity} operand(s), got {}", node.operator(), children.len()));
            }
            for c in children {
                this.compile(c, allowed)?;
            }
            this.ops.push(op);
            Ok(())
        };
        match node.operator() {
            Operator::RootNode => match children {
                [] => Ok(()),
                [only] => self.compile(only, allowed),
                _ => Err(format!("the expression \"{text}\" is not a single arithmetic expression")),
            },
            Operator::Add => binary(Op::Add, self),
            Operator::Sub => binary(Op::Sub, self),
            Operator::Mul => binary(Op::Mul, self),
            Operator::Div => binary(Op::Div, self),
            Operator::Neg => binary(Op::Neg, self),
            Operator::Exp => {
                if matches!(children.first().map(|c| c.operator()), Some(Operator::Exp)) {
                    return Err(format!("in \"{text}\", a^b^c is ambiguous (evalexpr reads (a^b)^c): write the parentheses"));
                }
                binary(Op::Pow, self)
            }
            Operator::Const { value } => {
                let v = match value {
                    Value::Float(f) => *f,
                    Value::Int(i) => *i as f64,
                    other => return Err(format!("in \"{text}\", {other} is not a number")),
                };
                self.ops.push(Op::Const(v));
                Ok(())
            }
            Operator::VariableIdentifierRead { identifier } => {
                if identifier == "pi" {
                    self.ops.push(Op::Const(std::f64::consts::PI));
                    return Ok(());
                }
                match VARIABLES.iter().position(|v| v == identifier).filter(|s| allowed.contains(s)) {
                    Some(slot) => {
                        self.uses |= 1 << slot;
                        self.ops.push(Op::Var(slot as u8));
                        Ok(())
                    }
                    None => {
                        let names: Vec<&str> = allowed.iter().map(|&s| VARIABLES[s]).collect();
                        Err(format!("the expression \"{text}\" uses the unknown variable `{identifier}` (this field's variables are {}; constant pi)", names.join(", ")))
                    }
                }
            }
            Operator::FunctionIdentifier { identifier } => {
                let name = identifier.strip_prefix("math::").unwrap_or(identifier);
                // The argument: one node, a tuple (RootNode → Tuple) for several.
                let args: Vec<&Node<DefaultNumericTypes>> = match children {
                    [arg] => match (arg.operator(), arg.children()) {
                        (Operator::RootNode, [inner]) if matches!(inner.operator(), Operator::Tuple) => inner.children().iter().collect(),
                        (Operator::RootNode, []) => Vec::new(),
                        (Operator::Tuple, c) => c.iter().collect(),
                        _ => vec![arg],
                    },
                    _ => children.iter().collect(),
                };
                let op = match (function1(name), function2(name), args.len()) {
                    (Some(f), _, 1) => Op::F1(f),
                    (_, Some(f), 2) => Op::F2(f),
                    (Some(_), _, n) | (_, Some(_), n) => {
                        let want = if function1(name).is_some() { 1 } else { 2 };
                        return Err(format!("in \"{text}\", {name} takes {want} argument(s), got {n}"));
                    }
                    _ => return Err(format!("in \"{text}\", `{identifier}` is not a known function (sin cos tan asin acos atan sinh cosh tanh exp ln log10 sqrt cbrt abs floor ceil; atan2 min max pow hypot)")),
                };
                for a in args {
                    self.compile(a, allowed)?;
                }
                self.ops.push(op);
                Ok(())
            }
            other => Err(format!("in \"{text}\", the operator `{other}` is not arithmetic (use + - * / ^, functions, parentheses)")),
        }
    }

    /// Largest number of values on the stack during evaluation; None if an operation
    /// would find too few operands or the program does not leave exactly one value.
    fn depth(&self) -> Option<usize> {
        let (mut d, mut most) = (0usize, 0usize);
        for op in &self.ops {
            match op {
                Op::Const(_) | Op::Var(_) => d += 1,
                Op::Neg | Op::F1(_) => {
                    if d < 1 {
                        return None;
                    }
                }
                _ => {
                    if d < 2 {
                        return None;
                    }
                    d -= 1;
                }
            }
            most = most.max(d);
        }
        (d == 1).then_some(most)
    }

    /// Whether the expression uses variable slot `slot` (0 x, 1 y, 2 z, 3 t).
    pub fn uses(&self, slot: usize) -> bool {
        self.uses & (1 << slot) != 0
    }

    /// Whether it uses x, y or z.
    pub fn uses_position(&self) -> bool {
        self.uses & 0b111 != 0
    }

    /// The value for variables `v` = [x, y, z, t] (unused slots are ignored).
    #[inline]
    pub fn eval(&self, v: &[f64; 4]) -> f64 {
        let mut stack = [0.0f64; MAX_DEPTH];
        let mut n = 0usize;
        for op in &self.ops {
            match *op {
                Op::Const(c) => {
                    stack[n] = c;
                    n += 1;
                }
                Op::Var(s) => {
                    stack[n] = v[s as usize];
                    n += 1;
                }
                Op::Neg => stack[n - 1] = -stack[n - 1],
                Op::F1(f) => stack[n - 1] = f(stack[n - 1]),
                op => {
                    let (a, b) = (stack[n - 2], stack[n - 1]);
                    n -= 1;
                    stack[n - 1] = match op {
                        Op::Add => a + b,
                        Op::Sub => a - b,
                        Op::Mul => a * b,
                        Op::Div => a / b,
                        Op::Pow => a.powf(b),
                        Op::F2(f) => f(a, b),
                        _ => unreachable!("handled above"),
                    };
                }
            }
        }
        stack[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    const XYT: &[usize] = &[0, 1, 3];

    fn ev(text: &str, v: [f64; 4]) -> f64 {
        Expr::parse(text, &[0, 1, 2, 3]).unwrap().eval(&v)
    }

    #[test]
    fn arithmetic_is_f64_with_the_usual_precedence() {
        let v = [2.0, 3.0, 5.0, 0.5];
        assert_eq!(ev("1/2*x", v), 1.0);
        assert_eq!(ev("-x^2", v), -4.0);
        assert_eq!(ev("exp(-x^2)", v), (-4.0f64).exp());
        assert_eq!(ev("1e-3*y", v), 1e-3 * 3.0);
        assert_eq!(ev("x*y + z - t", v), 2.0 * 3.0 + 5.0 - 0.5);
        assert_eq!(ev("(x^2)^3", v), 64.0);
        assert_eq!(ev("x^(2^3)", v), 256.0);
        assert_eq!(ev("atan2(y, x)", v), 3.0f64.atan2(2.0));
        assert_eq!(ev("min(t / 2, 1) * max(x, y)", v), 0.25 * 3.0);
        assert_eq!(ev("math::sin(pi * t)", v), (std::f64::consts::PI * 0.5).sin());
        assert_eq!(ev("sqrt(hypot(x, y))", v), 2.0f64.hypot(3.0).sqrt());
        assert_eq!(ev("7", v), 7.0);
        assert_eq!(ev("-(x - 2*y)", v), 4.0);
    }

    #[test]
    fn bad_expressions_are_named() {
        let err = |t: &str| Expr::parse(t, XYT).unwrap_err();
        assert!(err("x +").contains("does not parse"), "{}", err("x +"));
        assert!(err("* x").contains("does not parse"), "{}", err("* x"));
        assert!(err("x * (y +)").contains("does not parse"), "{}", err("x * (y +)"));
        assert!(err("sin()").contains("argument"), "{}", err("sin()"));
        assert!(err("z * x").contains("unknown variable `z`"), "{}", err("z * x"));
        assert!(err("foo").contains("unknown variable `foo`"));
        assert!(err("x^2^3").contains("ambiguous"));
        assert!(err("sinus(x)").contains("not a known function"));
        assert!(err("atan2(x)").contains("takes 2 argument"));
        assert!(err("x > 1").contains("not arithmetic"));
        assert!(err("x = 1").contains("not arithmetic"));
        assert!(err("x; y").contains("not arithmetic"));
        assert!(err("true").contains("not a number"));
        assert!(err("\"a\"").contains("not a number"));
        assert!(err("").contains("empty"));
    }

    #[test]
    fn uses_reports_the_variables() {
        let e = Expr::parse("x * t", XYT).unwrap();
        assert!(e.uses(0) && !e.uses(1) && e.uses(T) && e.uses_position());
        let e = Expr::parse("sin(t)", XYT).unwrap();
        assert!(!e.uses_position() && e.uses(T));
    }
}
