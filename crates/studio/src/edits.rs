//! Each page's editing session ([`relief::pipeline::EditSession`]): what its last previews
//! left (an island as its operations shaped it), so that its next edit is applied to it rather
//! than the whole history being replayed.

use std::sync::{Arc, Mutex, PoisonError};

use relief::pipeline::EditSession;

/// How many sessions' states are kept (the most recently used; each holds up to two islands of
/// at most 2²⁰ cells, about 25 MiB each).
const KEPT: usize = 4;

/// The kept editing sessions, least recently used first. A generation locks its session on its
/// blocking thread for as long as it runs, so a newer generation of the same page waits for a
/// superseded one to stop (at its next step or unit of work) and then resumes from what it kept.
#[derive(Debug, Default)]
pub(crate) struct EditSessions {
    kept: Mutex<Vec<(String, Arc<Mutex<EditSession>>)>>,
}

impl EditSessions {
    /// `name`'s session (a new one if none is kept), now the most recently used.
    pub(crate) fn get(&self, name: &str) -> Arc<Mutex<EditSession>> {
        let mut kept = self.kept.lock().unwrap_or_else(PoisonError::into_inner);
        let session = match kept.iter().position(|(n, _)| n == name) {
            Some(k) => kept.remove(k).1,
            None => Arc::default(),
        };
        kept.push((name.to_owned(), Arc::clone(&session)));
        if kept.len() > KEPT {
            kept.remove(0);
        }
        session
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_session_comes_back_and_the_least_recently_used_go() {
        let sessions = EditSessions::default();
        let first = sessions.get("s0");
        assert!(Arc::ptr_eq(&first, &sessions.get("s0")), "the same session each time");
        for k in 1..=KEPT {
            sessions.get(&format!("s{k}"));
        }
        let names: Vec<String> = sessions.kept.lock().unwrap().iter().map(|(n, _)| n.clone()).collect();
        assert_eq!(names.len(), KEPT);
        assert!(!names.contains(&"s0".to_owned()), "the least recently used went: {names:?}");
        assert!(!Arc::ptr_eq(&first, &sessions.get("s0")), "a forgotten session starts anew");
    }
}
