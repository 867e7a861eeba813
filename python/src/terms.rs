//! Messages in Python terms: the analyses' messages name the CLI's flags (`--allow-unstable`,
//! `--steps 0`); a Python caller passes keyword arguments (`allow_unstable=True`,
//! `steps=0`), and reads those names instead.

/// Each CLI flag a message may name and the keyword argument it is in Python; a flag that
/// takes a value keeps the value after `=` (`--steps 0` → `steps=0`).
const FLAGS: [(&str, &str, bool); 12] = [
    ("--allow-unstable", "allow_unstable=True", false),
    ("--settle", "settle=True", false),
    ("--static-first", "static_first=True", false),
    ("--start-at-equilibrium", "start_at_equilibrium=True", false),
    ("--lenient-arguments", "lenient_arguments=True", false),
    ("--no-damping", "no_damping=True", false),
    ("--end", "end", true),
    ("--steps", "steps", true),
    ("--dtout", "dtout", true),
    ("--shift", "shift", true),
    ("--time-limit", "time_limit", true),
    ("--deactivate", "deactivate", true),
];

/// `message` with every CLI flag of [`FLAGS`] written as its keyword argument: `--steps 0`
/// → `steps=0`, `--steps must be …` → `steps must be …`, `pass --allow-unstable` →
/// `pass allow_unstable=True`. A flag is only replaced as a whole word (`--end-time` is not
/// `--end`).
pub fn python_terms(message: &str) -> String {
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    'scan: while let Some(at) = rest.find("--") {
        out.push_str(&rest[..at]);
        let here = &rest[at..];
        for (flag, keyword, takes_value) in FLAGS {
            let Some(after) = here.strip_prefix(flag) else {
                continue;
            };
            let next = after.chars().next();
            if next.is_some_and(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
                continue;
            }
            out.push_str(keyword);
            rest = after;
            // `--steps 0`: the value follows a space; `--steps must …`: words follow.
            if takes_value {
                if let Some(value) = after.strip_prefix(' ') {
                    let word: String = value
                        .chars()
                        .take_while(|c| !c.is_whitespace() && *c != ',' && *c != ';')
                        .collect();
                    let is_value = word.chars().next().is_some_and(|c| {
                        c.is_ascii_digit() || c == '-' || c == '.' || c.is_ascii_uppercase()
                    });
                    if is_value && word != "-" {
                        out.push('=');
                        out.push_str(&word);
                        rest = &value[word.len()..];
                    }
                }
            }
            continue 'scan;
        }
        out.push_str("--");
        rest = &here[2..];
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::python_terms;

    #[test]
    fn flags_become_keyword_arguments() {
        assert_eq!(
            python_terms(
                "the equilibrium is UNSTABLE: try --settle (damped dynamics finds a stable \
                 one), or pass --allow-unstable to accept it"
            ),
            "the equilibrium is UNSTABLE: try settle=True (damped dynamics finds a stable \
             one), or pass allow_unstable=True to accept it"
        );
        assert_eq!(
            python_terms("--steps must be at least 1"),
            "steps must be at least 1"
        );
        assert_eq!(
            python_terms("--dtout 0.001 over --end 1000 asks for 1000000 outputs"),
            "dtout=0.001 over end=1000 asks for 1000000 outputs"
        );
        assert_eq!(
            python_terms("--deactivate CONTACT_1 runs the rest of the model without it"),
            "deactivate=CONTACT_1 runs the rest of the model without it"
        );
        // Not a flag of the table, or not a whole flag: unchanged.
        assert_eq!(python_terms("a --b and --end-time"), "a --b and --end-time");
    }
}
