#pragma once
// Facts about the running process that reports record.

namespace quadcage {

/// Peak resident memory of this process so far (getrusage's ru_maxrss), in MiB (2^20 bytes).
/// Thread-safe; never throws (0 if the system does not say).
double peak_memory_mib();

}  // namespace quadcage
