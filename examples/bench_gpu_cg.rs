fn main() {
    match knitsim::gpu::GpuContext::new() {
        Ok(c) => println!("{}", c.adapter),
        Err(e) => println!("{e}"),
    }
}
