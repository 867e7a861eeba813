//! Value helpers of the typing layer: numbers, ids, words, flags, functions and the choice of
//! one keyword among several, each with its error at the argument's place.

use super::*;

impl Typer {
    /// The numbers of an argument, each with its position; an error for any other value.
    pub(super) fn numbers(&mut self, st: &Statement, arg: &Argument) -> Option<Vec<(f64, Span)>> {
        let mut out = Vec::with_capacity(arg.values.len());
        for v in &arg.values {
            match v {
                Value::Number { value, span, .. } => out.push((*value, *span)),
                other => {
                    let msg = format!("'{}' of {} expects numbers", arg.key, label(st));
                    self.error(other.span(), msg);
                    return None;
                }
            }
        }
        Some(out)
    }

    /// `key = r1, …` with a count among `counts`.
    pub(super) fn reals(
        &mut self,
        st: &Statement,
        key: &str,
        counts: &[usize],
    ) -> Option<Located<Vec<f64>>> {
        let arg = st.arg(key)?;
        let nums = self.numbers(st, arg)?;
        if !counts.contains(&nums.len()) {
            let expected = match counts {
                [n] => n.to_string(),
                [a, b] if b == &(a + 1) => format!("{a} or {b}"),
                [first, .., last] if counts.len() > 2 => format!("{first} to {last}"),
                _ => counts
                    .iter()
                    .map(usize::to_string)
                    .collect::<Vec<_>>()
                    .join(" or "),
            };
            let msg = format!(
                "'{key}' of {} needs {expected} value{}, found {}",
                label(st),
                if expected == "1" { "" } else { "s" },
                nums.len()
            );
            self.error(arg.span, msg);
            return None;
        }
        Some(Located {
            value: nums.iter().map(|(v, _)| *v).collect(),
            span: arg.span,
        })
    }

    pub(super) fn real(&mut self, st: &Statement, key: &str) -> Option<Located<f64>> {
        let arg = st.arg(key)?;
        if let [Value::Number { value, .. }] = arg.values.as_slice() {
            return Some(Located {
                value: *value,
                span: arg.span,
            });
        }
        // Anything else is an error: [`Self::reals`] says which.
        let r = self.reals(st, key, &[1])?;
        Some(Located {
            value: r.value.first().copied().unwrap_or(0.0),
            span: r.span,
        })
    }

    pub(super) fn vec3(&mut self, st: &Statement, key: &str) -> Option<Located<[f64; 3]>> {
        let arg = st.arg(key)?;
        if let [Value::Number { value: a, .. }, Value::Number { value: b, .. }, Value::Number { value: c, .. }] =
            arg.values.as_slice()
        {
            return Some(Located {
                value: [*a, *b, *c],
                span: arg.span,
            });
        }
        // Anything else is an error: [`Self::reals`] says which.
        let r = self.reals(st, key, &[3])?;
        match r.value.as_slice() {
            [a, b, c] => Some(Located {
                value: [*a, *b, *c],
                span: r.span,
            }),
            _ => None,
        }
    }

    /// A number that is an id (a non-negative integer written without `D`).
    pub(super) fn as_id(&mut self, st: &Statement, key: &str, value: &Value) -> Option<IdRef> {
        match value {
            Value::Number {
                value,
                degrees: false,
                span,
            } if value.fract() == 0.0 && *value >= 0.0 && *value <= MAX_EXACT_ID => Some(IdRef {
                // Exact: an integral value within f64's exact integer range.
                id: *value as u64,
                span: *span,
            }),
            other => {
                let msg = format!(
                    "'{key}' of {} must be an id (a non-negative integer)",
                    label(st)
                );
                self.error(other.span(), msg);
                None
            }
        }
    }

    pub(super) fn id_ref(&mut self, st: &Statement, key: &str) -> Option<IdRef> {
        if let Some([value]) = st.arg(key).map(|a| a.values.as_slice()) {
            return self.as_id(st, key, value);
        }
        let ids = self.id_list(st, key, &[1])?;
        ids.first().copied()
    }

    /// `key = id1, id2, …` with a count among `counts`.
    pub(super) fn id_list(
        &mut self,
        st: &Statement,
        key: &str,
        counts: &[usize],
    ) -> Option<Vec<IdRef>> {
        let arg = st.arg(key)?;
        if !counts.contains(&arg.values.len()) {
            let expected = counts
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(" or ");
            let msg = format!(
                "'{key}' of {} needs {expected} id{}, found {}",
                label(st),
                if expected == "1" { "" } else { "s" },
                arg.values.len()
            );
            self.error(arg.span, msg);
            return None;
        }
        let mut ids = Vec::with_capacity(arg.values.len());
        for v in &arg.values {
            ids.push(self.as_id(st, key, v)?);
        }
        Some(ids)
    }

    /// Like [`Self::id_ref`], but an error at the statement when the argument is missing.
    pub(super) fn required_id(&mut self, st: &Statement, key: &str, what: &str) -> Option<IdRef> {
        if st.arg(key).is_none() {
            let msg = format!("{} needs {key} = <{what} id>", label(st));
            self.error(st.span, msg);
            return None;
        }
        self.id_ref(st, key)
    }

    /// The single word of `key = WORD`.
    pub(super) fn word<'s>(&mut self, st: &'s Statement, key: &str) -> Option<(&'s str, Span)> {
        let arg = st.arg(key)?;
        match arg.values.as_slice() {
            [Value::Word { text, span }] => Some((text.as_str(), *span)),
            _ => {
                let msg = format!("'{key}' of {} needs one word", label(st));
                self.error(arg.span, msg);
                None
            }
        }
    }

    /// `key = NAME` where NAME is one of `names` (by unambiguous prefix).
    pub(super) fn named(
        &mut self,
        st: &Statement,
        key: &str,
        names: &[&'static str],
    ) -> Option<Located<String>> {
        let (word, span) = self.word(st, key)?;
        match keywords::lookup_name(word, names) {
            Lookup::Found(name) => Some(Located {
                value: name.to_string(),
                span,
            }),
            Lookup::Ambiguous(candidates) => {
                let msg = format!(
                    "ambiguous value '{word}' of '{key}': could be {}",
                    candidates.join(", ")
                );
                self.error(span, msg);
                None
            }
            Lookup::NotFound => {
                let msg = format!(
                    "unknown value '{word}' of '{key}' (expected one of {})",
                    names.join(", ")
                );
                self.error(span, msg);
                None
            }
        }
    }

    /// The statement's `ROUTINE = lib::name` text, trimmed (`None`: absent or empty).
    fn routine(st: &Statement) -> Option<String> {
        let text = match st.arg("ROUTINE")?.values.first()? {
            Value::Expr(e) => e.text.clone(),
            Value::Str { text, .. } | Value::Word { text, .. } => text.clone(),
            Value::Number { .. } => return None,
        };
        let text = text.trim().to_string();
        (!text.is_empty()).then_some(text)
    }

    pub(super) fn flag(st: &Statement, key: &str) -> bool {
        st.arg(key).is_some()
    }

    pub(super) fn function(&mut self, st: &Statement, key: &str) -> Option<Located<Function>> {
        let arg = st.arg(key)?;
        match arg.values.as_slice() {
            [Value::Expr(expr)] => Some(Located {
                value: Function {
                    expr: expr.clone(),
                    user: is_user_call(&expr.text),
                    routine: is_user_call(&expr.text)
                        .then(|| Self::routine(st))
                        .flatten(),
                },
                span: expr.span_at(0),
            }),
            _ => {
                let msg = format!("'{key}' of {} needs an expression", label(st));
                self.error(arg.span, msg);
                None
            }
        }
    }

    /// The arguments of `st` that are one of `kinds` (canonical keys), in order.
    pub(super) fn pick<'s, T: Copy>(
        st: &'s Statement,
        kinds: &[(&str, T)],
    ) -> Vec<(&'s Argument, T)> {
        st.args
            .iter()
            .filter_map(|a| {
                kinds
                    .iter()
                    .find(|(k, _)| *k == a.key)
                    .map(|(_, t)| (a, *t))
            })
            .collect()
    }

    /// At most one of `kinds`; an error at the second one otherwise.
    pub(super) fn one_of<T: Copy>(
        &mut self,
        st: &Statement,
        kinds: &[(&str, T)],
        what: &str,
    ) -> Result<Option<T>, ()> {
        let mut found = st.args.iter().filter_map(|a| {
            kinds
                .iter()
                .find(|(k, _)| *k == a.key)
                .map(|(_, t)| (a, *t))
        });
        match (found.next(), found.next()) {
            (None, _) => Ok(None),
            (Some((_, t)), None) => Ok(Some(t)),
            (Some((first, _)), Some((second, _))) => {
                let msg = format!(
                    "{} has more than one {what} ('{}' and '{}')",
                    label(st),
                    first.key,
                    second.key
                );
                self.error(second.span, msg);
                Err(())
            }
        }
    }

    /// Bare words of `st` that its (complete) table does not know, for error hints.
    pub(super) fn unknown_words(st: &Statement) -> Vec<String> {
        let def = keywords::DATASET_STATEMENTS
            .iter()
            .find(|d| d.name == st.keyword);
        st.args
            .iter()
            .filter(|a| {
                a.values.is_empty() && def.is_some_and(|d| keywords::arg_def(d, &a.key).is_none())
            })
            .map(|a| format!("'{}'", a.key))
            .collect()
    }
}
