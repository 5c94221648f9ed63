#pragma once
// What the kernel says of this process's memory (Linux /proc; getrusage
// where /proc is not mounted).

namespace cogmap {

// The peak resident set of this program since it started, KiB: VmHWM of
// /proc/self/status, which belongs to this image alone. (getrusage's
// ru_maxrss is the fallback only: exec keeps the launcher's peak in it, so a
// program started by a large process reports that process's memory.)
long PeakResidentKib();

// The resident set now, KiB (VmRSS); 0 when unknown.
long ResidentKib();

}  // namespace cogmap
