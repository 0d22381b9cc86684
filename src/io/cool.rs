//! cooler reader/writer. Being written.
