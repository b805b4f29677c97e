//! Each page's editing session ([`relief::pipeline::EditSession`]): what its last previews
//! left (an island as its operations shaped it), so that its next edit is applied to it rather
//! than the whole history being replayed.

use std::sync::{Mutex, PoisonError};

use relief::pipeline::EditSession;

/// How many sessions' states are kept (the most recently used; each holds up to two islands).
const KEPT: usize = 8;

/// The kept editing sessions, least recently used first.
#[derive(Debug, Default)]
pub(crate) struct EditSessions {
    kept: Mutex<Vec<(String, EditSession)>>,
}

impl EditSessions {
    /// `name`'s session, taken out while a generation uses it (a new one if none is kept).
    pub(crate) fn take(&self, name: &str) -> EditSession {
        let mut kept = self.kept.lock().unwrap_or_else(PoisonError::into_inner);
        kept.iter().position(|(n, _)| n == name).map(|k| kept.remove(k).1).unwrap_or_default()
    }

    /// Puts `name`'s session back as the most recently used, forgetting the least recently used
    /// beyond [`KEPT`].
    pub(crate) fn put(&self, name: String, session: EditSession) {
        let mut kept = self.kept.lock().unwrap_or_else(PoisonError::into_inner);
        kept.retain(|(n, _)| *n != name);
        kept.push((name, session));
        if kept.len() > KEPT {
            kept.remove(0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sessions_come_back_and_the_least_recently_used_go() {
        let sessions = EditSessions::default();
        for k in 0..=KEPT {
            sessions.put(format!("s{k}"), EditSession::new());
        }
        let names =
            |s: &EditSessions| -> Vec<String> { s.kept.lock().unwrap().iter().map(|(n, _)| n.clone()).collect() };
        assert_eq!(names(&sessions).len(), KEPT);
        assert!(!names(&sessions).contains(&"s0".to_owned()), "the oldest went");
        let _taken = sessions.take("s1");
        assert!(!names(&sessions).contains(&"s1".to_owned()), "taken out while in use");
        sessions.put("s1".into(), EditSession::new());
        assert_eq!(names(&sessions).last().map(String::as_str), Some("s1"), "now the most recent");
    }
}
