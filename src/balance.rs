//! Matrix balancing (ICE, VC, VC_SQRT, KR). Being written.
