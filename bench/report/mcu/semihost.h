/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench/report/mcu/semihost.h - the three semihosting calls the report's image uses. */
#ifndef ZW_REPORT_SEMIHOST_H
#define ZW_REPORT_SEMIHOST_H
int semihost_call(int op, const void *arg);
void semihost_exit(int ok);
void semihost_puts(const char *s);
#endif
