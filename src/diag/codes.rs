//! The registry of diagnostic codes.
//!
//! Each code is declared once here with a one-line title; its explanation is the page
//! `docs/diagnostics/CODE.md`, embedded in the binary so `kbc explain CODE` works anywhere.
//! A missing page is a compile error. `tests/diagnostic_registry.rs` checks the other
//! direction (every page is registered) and that every code has a UI test.
//!
//! Ranges: E01xx reading and syntax, E02xx structure, names and arities, E03xx planning,
//! E04xx temporal, E05xx back end, E06xx drafting (`kbc draft`), Wxxxx warnings. Codes are never reused.

use std::fmt;

/// A stable diagnostic code such as `E0102`.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Code(&'static str);

impl Code {
    /// The code's text, e.g. `"E0102"`.
    pub fn as_str(self) -> &'static str {
        self.0
    }

    /// The registry entry for this code.
    pub fn info(self) -> &'static CodeInfo {
        ALL.iter().find(|info| info.code == self.0).expect("every Code constant is registered")
    }
}

impl fmt::Debug for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}

impl fmt::Display for Code {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}

impl serde::Serialize for Code {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.0)
    }
}

/// A code's registry entry.
#[derive(Debug)]
pub struct CodeInfo {
    /// The code, e.g. `"E0102"`.
    pub code: &'static str,
    /// A one-line summary.
    pub title: &'static str,
    /// The Markdown page from docs/diagnostics/.
    pub explanation: &'static str,
}

/// Looks a code up by its text, accepting any letter case (`e0102`).
pub fn lookup(code: &str) -> Option<&'static CodeInfo> {
    ALL.iter().find(|info| info.code.eq_ignore_ascii_case(code))
}

macro_rules! codes {
    ($($name:ident = $code:literal : $title:literal;)*) => {
        $(
            #[doc = $title]
            pub const $name: Code = Code($code);
        )*
        /// Every registered code, in numeric order.
        pub const ALL: &[CodeInfo] = &[
            $(CodeInfo {
                code: $code,
                title: $title,
                explanation: include_str!(concat!("../../docs/diagnostics/", $code, ".md")),
            },)*
        ];
    };
}

codes! {
    // Reading and syntax.
    UNEXPECTED_TOKEN = "E0101": "unexpected token";
    MISSING_PERIOD = "E0102": "missing `.` at the end of a clause";
    UNCLOSED_DELIMITER = "E0103": "unclosed delimiter";
    MISMATCHED_DELIMITER = "E0104": "mismatched or unexpected closing delimiter";
    UNTERMINATED_QUOTED = "E0105": "unterminated quoted atom or string";
    UNTERMINATED_COMMENT = "E0106": "unterminated block comment";
    NOT_AN_OPERATOR = "E0107": "an operator from another language (`!=`, `<=`, `&&`)";
    SPACE_BEFORE_PAREN = "E0108": "space between a functor and its `(`";
    MISSING_COMMA = "E0109": "missing `,` between list elements, arguments or goals";
    UNSUPPORTED_OPERATOR = "E0110": "user-defined or unsupported operator";
    UNEXPECTED_CHARACTER = "E0111": "unexpected character";
    BAD_NUMBER = "E0112": "number literal out of range";
    BAD_ESCAPE = "E0113": "unknown escape sequence";
    VARIABLE_FUNCTOR = "E0114": "variable used as a predicate name";
    CLAUSE_TOO_LONG = "E0115": "a clause longer than the limit";
    UNREADABLE_FILE = "E0120": "file cannot be read";
    LOAD_CYCLE = "E0121": "`include` or `ensure_loaded` cycle";
    BAD_LOAD_DIRECTIVE = "E0122": "malformed `include` or `ensure_loaded`";
    // Structure, names and arities.
    ACTION_ARITY = "E0201": "`action` or `ll_action` with the wrong number of arguments";
    SLOT_NOT_LIST = "E0202": "an action slot that is not a list";
    BAD_EFFECT = "E0203": "an effect other than `add(L)` or `del(L)`";
    UNPAIRED_DURATIVE = "E0204": "an arm-level `_start` without its `_end`, or the reverse";
    DURATIVE_ARITY = "E0205": "`_start` and `_end` with different arities";
    DUPLICATE_ACTION = "E0206": "duplicate action schema";
    UNKNOWN_MAPPED_ACTION = "E0207": "a mapping to an unknown action";
    INCOMPLETE_PROBLEM = "E0208": "a problem without an init or a goal state";
    NON_GROUND_INIT = "E0209": "an init fact that is not ground (no longer emitted)";
    UNKNOWN_PREDICATE = "E0210": "unknown predicate";
    WRONG_ARITY = "E0211": "a predicate used with a different arity";
    UNREACHABLE_GOAL = "E0212": "a goal literal nothing can make true";
    UNBOUND_EFFECT_VARIABLE = "E0213": "a goal that needs an effect variable nothing binds";
    NOT_CALLABLE = "E0214": "a literal or action name that is not an atom or compound";
    BAD_PROBLEM = "E0215": "a malformed problem";
    BAD_DURATION = "E0216": "a malformed `duration/3`";
    BAD_DECLARATION = "E0217": "a malformed declaration: `dynamic`, `discontiguous`, `mapping/2`, `resources/1`";
    BAD_CLAUSE_HEAD = "E0218": "a clause head that cannot be defined";
    // Planning.
    UNKNOWN_PROBLEM = "E0301": "no problem of that name";
    AMBIGUOUS_PROBLEM = "E0302": "several problems and no `--problem`";
    NO_PROBLEM = "E0303": "no problem to plan";
    NO_PLAN = "E0304": "the search space holds no plan";
    SEARCH_BUDGET = "E0305": "a search budget ran out";
    UNREACHABLE_GOAL_RELAXED = "E0306": "a goal literal no sequence of actions can reach";
    EXCLUSIVE_GOALS = "E0307": "goal literals that can never hold together";
    CONDITION_ERROR = "E0308": "an OnKB goal failed with an error";
    INVALID_PLAN = "E0309": "a plan step that does not apply";
    BAD_PLAN_FILE = "E0310": "a plan file that cannot be read as steps";
    REFINEMENT_FAILED = "E0311": "a plan that does not refine into arm-level actions";
    // Temporal.
    INCONSISTENT_STN = "E0401": "durations and orderings that no schedule satisfies";
    BAD_DURATION_VALUE = "E0402": "a duration that cannot be used";
    INVALID_SCHEDULE = "E0403": "a timed plan that does not execute";
    EXPORT_INEXPRESSIBLE = "E0404": "a KB construct PDDL cannot express";
    EXPORT_TOO_LARGE = "E0405": "an export that would be too large";
    // Back end and VM.
    BAD_BYTECODE = "E0501": "a bytecode file that does not load";
    RUN_FAILED = "E0502": "a behaviour tree that did not succeed";
    NOT_PROVIDED = "E0503": "an action the host can neither run nor refine";
    UNBOUND_MAPPING = "E0504": "a mapping that leaves a step's variable unbound";
    GOAL_NOT_REACHED = "E0505": "a run whose world does not satisfy the goal";
    CANNOT_RECOVER = "E0506": "a fault the run cannot recover from";
    // Drafting with a language model (`kbc draft`): states a test case must be.
    BLOCK_TWO_PLACES = "E0601": "a block in two places in one state";
    BLOCK_NOWHERE = "E0602": "a block named in a state without a place in it";
    SUPPORT_ELSEWHERE = "E0603": "a block stacked on a block that is somewhere else";
    SUPPORT_SHARED = "E0604": "two blocks on one block or one cell";
    STACK_CYCLE = "E0605": "blocks stacked on each other in a cycle";
    CLEAR_WRONG = "E0606": "`clear/1` on a covered block, or missing on an uncovered one";
    UNKNOWN_POSITION = "E0607": "a position the KB's `pos/2` does not know";
    UNKNOWN_AGENT = "E0608": "an agent the initial state does not have";
    BLOCKS_DIFFER = "E0609": "initial state and goal over different blocks";
    NO_CODE = "E0610": "a model's answer without code";
    NOT_ASKED_FOR = "E0611": "a model's answer that does not hold what was asked for";
    // Warnings.
    SINGLETON_VARIABLE = "W0001": "singleton variable";
    NEVER_PRODUCED = "W0002": "a condition or deletion on a predicate nothing produces";
    IGNORED_DIRECTIVE = "W0003": "directive ignored";
    MARKED_SINGLETON_REUSED = "W0004": "a `_`-prefixed variable used more than once";
    DISCONTIGUOUS = "W0005": "clauses of a predicate not together";
    DEFAULT_DURATION = "W0006": "a durative action without a duration";
    EXPORT_LEAVES_OUT = "W0007": "a KB part the PDDL export leaves out";
    ARITY_NEVER_MATCHES = "W0008": "a state literal with an arity no state fact has";
    OPEN_DELETE = "W0009": "a `del` with a variable nothing binds";
    OPEN_ADD = "W0010": "an `add` with a variable nothing binds";
    UNPAIRED_ARITIES = "W0011": "a `_start` and an `_end` with different arities, planned as unrelated actions";
    MISSPELT_DECLARATION = "W0012": "a fact named like a kbc declaration";
    UNUSED_DURATION = "W0013": "a duration that names no durative action";
    INCLUDED_AGAIN = "W0014": "a file included again";
    OPEN_INIT = "W0015": "an initial fact with a variable";
    OUTPUT_NOT_PRINTED = "W0016": "output that kbc does not print";
    GOALS_AFTER_GO = "W0017": "goals of a test after its `go` call, which kbc does not run";
    EMPTY_DURATION = "W0018": "a `duration/3` whose least duration is above its greatest";
    UNPAIRED_SNAP = "W0019": "a `_start` without an `_end`, or the reverse, planned as an instantaneous action";
    UNDEFINED_IN_RULE_NEVER_RUN = "W0020": "an undefined predicate called in a rule planning never runs";
}

/// Codes kbc no longer emits. Their pages stay, so `kbc explain` answers for output of older
/// versions, and say what replaced them; codes are never reused.
pub const RETIRED: &[&str] = &["E0209"];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_unique_sorted_and_documented() {
        for pair in ALL.windows(2) {
            assert!(
                pair[0].code < pair[1].code || pair[0].code.starts_with('E') && pair[1].code.starts_with('W'),
                "{} and {} out of order",
                pair[0].code,
                pair[1].code
            );
        }
        for info in ALL {
            assert!(
                info.explanation.starts_with(&format!("# {}", info.code)),
                "{} page must start with its code",
                info.code
            );
        }
    }

    #[test]
    fn lookup_ignores_case() {
        assert_eq!(lookup("e0102").map(|i| i.code), Some("E0102"));
        assert!(lookup("E9999").is_none());
    }
}
