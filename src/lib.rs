pub mod envmap;
