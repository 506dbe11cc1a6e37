/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

#include "zwidth/status.h"

const char *zw_status_name(zw_status status)
{
    switch (status) {
    case ZW_OK: return "ZW_OK";
    case ZW_ERR_NULL: return "ZW_ERR_NULL";
    case ZW_ERR_NAN: return "ZW_ERR_NAN";
    case ZW_ERR_INF: return "ZW_ERR_INF";
    case ZW_ERR_MASS: return "ZW_ERR_MASS";
    case ZW_ERR_PERIOD: return "ZW_ERR_PERIOD";
    case ZW_ERR_DAMPING: return "ZW_ERR_DAMPING";
    case ZW_ERR_DELTA: return "ZW_ERR_DELTA";
    case ZW_ERR_RANGE: return "ZW_ERR_RANGE";
    case ZW_ERR_ARG: return "ZW_ERR_ARG";
    case ZW_ERR_DOMAIN: return "ZW_ERR_DOMAIN";
    case ZW_ERR_FPENV: return "ZW_ERR_FPENV";
    case ZW_ERR_DELAY: return "ZW_ERR_DELAY";
    case ZW_ERR_FILTER: return "ZW_ERR_FILTER";
    case ZW_ERR_BUSY: return "ZW_ERR_BUSY";
    case ZW_ERR_BOX: return "ZW_ERR_BOX";
    default: break; /* a value outside the enumeration: named below */
    }
    return "ZW_UNKNOWN";
}
