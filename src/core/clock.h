// clock.h — a monotonic clock in seconds, for build and render times (never for anything an image depends on).
#ifndef GLINT_CLOCK_H
#define GLINT_CLOCK_H

/// Seconds on the monotonic clock since an arbitrary start; only differences mean anything.
double clock_seconds(void);

#endif
