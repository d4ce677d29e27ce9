//! Static Q4 finite elements (in progress).
