//! Distance-decay expected and power-law fits. Being written.
