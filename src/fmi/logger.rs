//! Messages to the importer's logger, with the FMI log categories and filters.
//!
//! Policy:
//! - Discard, error and fatal messages always reach the logger: they explain a refused or
//!   failed call and an importer cannot act without them.
//! - Warnings, events and solver messages are sent only when debug logging is on (`loggingOn`
//!   at instantiation or `fmi2SetDebugLogging`) and their category is enabled.
//! - Without a logger callback, those messages go to stderr, prefixed with the
//!   instance name; nothing else is printed.
//!
//! The logger is variadic and printf-style, so it is always called with the format `"%s"` and the
//! message as its argument: a `%` in a message can never be read as a conversion.
//!
//! A message longer than [`MAX_MESSAGE`] bytes (a message that echoes a 10 MB string the importer
//! passed, say) is cut at a character boundary after [`MAX_MESSAGE`] bytes and ends with
//! `... (N more characters)` ([`clip`]), whatever the sink.

use std::borrow::Cow;
use std::ffi::{CStr, CString};

use super::types::*;

/// A log category declared in `modelDescription.xml`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Category {
    /// Messages accompanying `fmi2Warning`.
    StatusWarning,
    /// Messages accompanying `fmi2Discard`.
    StatusDiscard,
    /// Messages accompanying `fmi2Error`.
    StatusError,
    /// Messages accompanying `fmi2Fatal`.
    StatusFatal,
    /// Model events (lock-up, saturation, contact changes).
    Events,
    /// Solver statistics and step-size decisions.
    Solver,
}

/// Every category with its name and description, in `LogCategories` order.
pub const CATEGORIES: [(Category, &CStr, &str); 6] = [
    (
        Category::StatusWarning,
        c"logStatusWarning",
        "Messages with status fmi2Warning.",
    ),
    (
        Category::StatusDiscard,
        c"logStatusDiscard",
        "Messages with status fmi2Discard: why a status query had no answer.",
    ),
    (
        Category::StatusError,
        c"logStatusError",
        "Messages with status fmi2Error: the reason a call failed.",
    ),
    (
        Category::StatusFatal,
        c"logStatusFatal",
        "Messages with status fmi2Fatal: internal errors.",
    ),
    (
        Category::Events,
        c"logEvents",
        "Model events such as saturation, lock-up or contact changes.",
    ),
    (
        Category::Solver,
        c"logSolver",
        "Solver statistics at fmi2Terminate and after a failed step (accepted steps, rejected steps by cause, Newton iterations and failures, Jacobians, factorizations, last step size), the use of the experiment tolerance, set-up notes; models without an integrator (PidController) emit none.",
    ),
];

impl Category {
    fn index(self) -> usize {
        self as usize
    }

    /// The category's name as declared in the model description.
    pub fn name(self) -> &'static CStr {
        CATEGORIES[self.index()].1
    }

    /// The category with this name.
    pub fn from_name(name: &[u8]) -> Option<Category> {
        CATEGORIES
            .iter()
            .find(|(_, n, _)| n.to_bytes() == name)
            .map(|(c, _, _)| *c)
    }
}

/// The importer's environment pointer, only ever passed back to its own logger.
#[derive(Debug, Clone, Copy)]
struct Env(fmi2ComponentEnvironment);

// SAFETY: the pointer is never dereferenced here; it is handed back to the importer's logger,
// which the FMI standard requires to accept calls from the thread that calls the instance.
unsafe impl Send for Env {}

/// Where messages go.
#[derive(Debug, Clone)]
enum Sink {
    /// The importer's callback.
    Importer(
        unsafe extern "C" fn(
            fmi2ComponentEnvironment,
            fmi2String,
            fmi2Status,
            fmi2String,
            fmi2String,
            ...
        ),
        Env,
    ),
    /// The importer's FMI 3.0 callback (`fmi3LogMessageCallback`: not variadic, no instance
    /// name).
    Importer3(
        unsafe extern "C" fn(
            super::types3::fmi3InstanceEnvironment,
            super::types3::fmi3Status,
            super::types3::fmi3String,
            super::types3::fmi3String,
        ),
        Env,
    ),
    /// No callback: stderr, for discard, error and fatal messages only.
    Stderr,
    /// Collected in memory (unit tests).
    #[cfg(test)]
    Capture(std::sync::Arc<std::sync::Mutex<Vec<Captured>>>),
}

/// A message collected by a test logger: status, category and text.
#[cfg(test)]
pub type Captured = (fmi2Status, Category, String);

/// The importer's logger plus the filters set by `loggingOn` and `fmi2SetDebugLogging`.
#[derive(Debug, Clone)]
pub struct Logger {
    sink: Sink,
    name: CString,
    logging_on: bool,
    enabled: [bool; CATEGORIES.len()],
}

impl Logger {
    /// A logger for the instance `name`; `callback` may be `None`.
    pub fn new(
        callback: fmi2CallbackLogger,
        env: fmi2ComponentEnvironment,
        name: &str,
        logging_on: bool,
    ) -> Self {
        let sink = match callback {
            Some(f) => Sink::Importer(f, Env(env)),
            None => Sink::Stderr,
        };
        Self::with_sink(sink, name, logging_on)
    }

    /// A logger for an FMI 3.0 instance `name`; `callback` may be `None`.
    pub fn new3(
        callback: super::types3::fmi3LogMessageCallback,
        env: super::types3::fmi3InstanceEnvironment,
        name: &str,
        logging_on: bool,
    ) -> Self {
        let sink = match callback {
            Some(f) => Sink::Importer3(f, Env(env)),
            None => Sink::Stderr,
        };
        Self::with_sink(sink, name, logging_on)
    }

    /// A logger writing to `sink` for the instance `name`, every category enabled.
    fn with_sink(sink: Sink, name: &str, logging_on: bool) -> Self {
        Self {
            sink,
            name: to_cstring(name),
            logging_on,
            enabled: [true; CATEGORIES.len()],
        }
    }

    /// A logger that collects messages in memory, for tests.
    #[cfg(test)]
    pub fn capture(
        name: &str,
        logging_on: bool,
    ) -> (Self, std::sync::Arc<std::sync::Mutex<Vec<Captured>>>) {
        let store = std::sync::Arc::new(std::sync::Mutex::new(Vec::new()));
        let sink = Sink::Capture(store.clone());
        (
            Self {
                sink,
                name: to_cstring(name),
                logging_on,
                enabled: [true; CATEGORIES.len()],
            },
            store,
        )
    }

    /// The instance name.
    pub fn instance_name(&self) -> &str {
        self.name.to_str().unwrap_or("?")
    }

    /// `fmi2SetDebugLogging`: with no categories, switches debug logging on or off and resets
    /// every category to enabled; with categories, enables (`on`) or disables them.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[Category]) {
        if categories.is_empty() {
            self.logging_on = on;
            self.enabled = [true; CATEGORIES.len()];
        } else {
            if on {
                self.logging_on = true;
            }
            for c in categories {
                self.enabled[c.index()] = on;
            }
        }
    }

    /// True when a message of this status and category would be delivered.
    pub fn passes(&self, status: fmi2Status, category: Category) -> bool {
        if matches!(self.sink, Sink::Stderr) {
            return status >= fmi2Discard;
        }
        status >= fmi2Discard || (self.logging_on && self.enabled[category.index()])
    }

    /// Sends `message` with its status and category, if the filters let it through; a message
    /// longer than [`MAX_MESSAGE`] bytes is cut ([`clip`]).
    pub fn log(&self, status: fmi2Status, category: Category, message: &str) {
        if !self.passes(status, category) {
            return;
        }
        let message = &*clip(message);
        match &self.sink {
            Sink::Importer(f, env) => {
                let msg = to_cstring(message);
                // SAFETY: the importer gave us this callback for exactly this call; every string
                // is NUL-terminated and outlives the call; the format is "%s" with one argument.
                unsafe {
                    f(
                        env.0,
                        self.name.as_ptr(),
                        status,
                        category.name().as_ptr(),
                        c"%s".as_ptr(),
                        msg.as_ptr(),
                    )
                }
            }
            Sink::Importer3(f, env) => {
                let msg = to_cstring(message);
                // SAFETY: as above; the FMI 3.0 logger takes the message as plain text.
                unsafe { f(env.0, status, category.name().as_ptr(), msg.as_ptr()) }
            }
            Sink::Stderr => {
                eprintln!(
                    "[{}] {}: {message}",
                    self.instance_name(),
                    category.name().to_string_lossy()
                );
            }
            #[cfg(test)]
            Sink::Capture(store) => {
                if let Ok(mut v) = store.lock() {
                    v.push((status, category, message.to_string()));
                }
            }
        }
    }
}

/// The longest message text sent to a logger, in bytes (before the `... (N more characters)`
/// suffix of a cut message).
pub const MAX_MESSAGE: usize = 4096;

/// `message`, or its first [`MAX_MESSAGE`] bytes (cut at a character boundary) followed by
/// `... (N more characters)` when it is longer.
pub fn clip(message: &str) -> Cow<'_, str> {
    if message.len() <= MAX_MESSAGE {
        return Cow::Borrowed(message);
    }
    let mut end = MAX_MESSAGE;
    while !message.is_char_boundary(end) {
        end -= 1;
    }
    let more = message[end..].chars().count();
    Cow::Owned(format!("{}... ({more} more characters)", &message[..end]))
}

/// `s` as a C string; interior NUL bytes are shown as `\0`.
pub fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', "\\0")).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_follow_the_policy() {
        let (mut l, _) = Logger::capture("x", false);
        assert!(l.passes(fmi2Error, Category::StatusError));
        assert!(l.passes(fmi2Fatal, Category::StatusFatal));
        assert!(!l.passes(fmi2OK, Category::Events));
        assert!(!l.passes(fmi2Warning, Category::StatusWarning));
        l.set_debug_logging(true, &[]);
        assert!(l.passes(fmi2OK, Category::Events));
        l.set_debug_logging(false, &[Category::Events]);
        assert!(!l.passes(fmi2OK, Category::Events));
        assert!(l.passes(fmi2OK, Category::Solver));
        l.set_debug_logging(false, &[]);
        assert!(!l.passes(fmi2OK, Category::Solver));
        assert_eq!(Category::from_name(b"logSolver"), Some(Category::Solver));
        assert_eq!(Category::from_name(b"logNope"), None);
        assert_eq!(to_cstring("a\0b").to_bytes(), b"a\\0b");
    }

    #[test]
    fn long_messages_are_cut_at_a_character_boundary() {
        assert!(matches!(clip("short"), Cow::Borrowed("short")));
        let exact = "x".repeat(MAX_MESSAGE);
        assert_eq!(clip(&exact), exact);
        let long = format!("{}{}", "a".repeat(MAX_MESSAGE - 1), "é".repeat(10));
        let cut = clip(&long);
        assert_eq!(
            cut,
            format!("{}... (10 more characters)", "a".repeat(MAX_MESSAGE - 1))
        );
        let (l, log) = Logger::capture("x", false);
        l.log(
            fmi2Error,
            Category::StatusError,
            &format!("name `{}`", "n".repeat(10_000_000)),
        );
        let got = log.lock().unwrap()[0].2.clone();
        assert!(got.len() < MAX_MESSAGE + 40, "{}", got.len());
        assert!(
            got.ends_with("... (9995911 more characters)"),
            "{}",
            &got[4000..]
        );
    }
}
