//! `contactmap expected` against the peer tools' reference outputs.
