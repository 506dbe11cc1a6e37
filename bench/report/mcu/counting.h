/* bench/report/mcu/counting.h - the counted images' markers (counting.c).
 *
 * report_marker(): called between the measured calls; mcu.count_segments splits QEMU's
 * instruction trace at its entry.  report_calibration(): exactly 605 instructions, which
 * the counter must report, or the report says the method failed. */
#ifndef ZW_REPORT_COUNTING_H
#define ZW_REPORT_COUNTING_H

void report_marker(void);
void report_calibration(void);

#endif /* ZW_REPORT_COUNTING_H */
