//! The Space Foosball game (being written).
