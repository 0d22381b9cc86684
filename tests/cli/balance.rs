//! `contactmap balance` against the peer tools' reference outputs.
