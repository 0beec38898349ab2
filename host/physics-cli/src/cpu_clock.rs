//! The thread's CPU clock for the accuracy report's cost columns
//! (`virtual_physics::measure::accuracy::set_clock`): on Linux `CLOCK_THREAD_CPUTIME_ID`, so
//! time the scheduler gives to other processes on a shared machine does not count;
//! elsewhere, or where the clock cannot be read, the library's wall clock stays.

/// Sets the accuracy report's clock to this thread's CPU time where the platform has one.
pub fn install() {
    #[cfg(target_os = "linux")]
    if thread_cpu_seconds().is_some() {
        virtual_physics::measure::accuracy::set_clock(|| thread_cpu_seconds().unwrap_or(f64::NAN));
    }
}

/// CPU seconds the calling thread has used, `None` if the clock cannot be read.
#[cfg(target_os = "linux")]
fn thread_cpu_seconds() -> Option<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant of the
    // platform; clock_gettime writes only into `ts`.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (rc == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}
