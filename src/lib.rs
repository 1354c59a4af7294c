pub mod shaders;
