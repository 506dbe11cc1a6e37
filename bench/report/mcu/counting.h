/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench/report/mcu/counting.h - the counted images' markers (counting.c).
 *
 * report_marker(): called between the measured calls; mcu.count_segments splits QEMU's
 * instruction trace at its entry.  report_calibration(): exactly 605 instructions, which
 * the counter must report, or the report says the method failed. */
#ifndef ZW_REPORT_COUNTING_H
#define ZW_REPORT_COUNTING_H

void report_marker(void);
void report_calibration(void);
/* The end of every counted run: the calibration between two markers, acc kept alive (so
 * the measured calls are not optimized away), "count done" on the semihosting console.
 * Its own instructions are the driver's (mcu.DRIVER_SYMBOLS), not counted. */
void report_count_done(unsigned long acc);

#endif /* ZW_REPORT_COUNTING_H */
