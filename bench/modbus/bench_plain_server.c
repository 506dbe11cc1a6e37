/*
 * SPDX-FileCopyrightText: 2026 The zwidth authors
 * SPDX-License-Identifier: Apache-2.0
 */

/* bench_plain_server.c - the baseline for bench_modbus: a plain libmodbus TCP server.
 *
 * modbus_mapping_new + modbus_reply, nothing else: every holding register 0x0000 ..
 * ZW_REG_COUNT-1 is read/write and no request is validated, so the difference between
 * zwidth-drive and this server is what certification (and the map's bookkeeping) costs.
 *
 *   bench_plain_server [--port P]     listens on 127.0.0.1:P (default 1503), one client at
 *                                     a time, until killed (SIGTERM).
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <modbus.h>

#include "zwidth/regmap.h"

int main(int argc, char **argv)
{
    int port = 1503;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--port") == 0 && i + 1 < argc) {
            char *end = NULL;
            long p = strtol(argv[++i], &end, 10);
            if (!end || *end != '\0' || p < 1 || p > 65535) {
                fprintf(stderr, "bench_plain_server: --port wants 1..65535, got %s\n", argv[i]);
                return 2;
            }
            port = (int)p;
        } else {
            fprintf(stderr, "usage: bench_plain_server [--port P]\n");
            return 2;
        }
    }

    modbus_t *ctx = modbus_new_tcp("127.0.0.1", port);
    modbus_mapping_t *map = modbus_mapping_new(0, 0, ZW_REG_COUNT, 0);
    if (!ctx || !map) {
        fprintf(stderr, "bench_plain_server: %s\n", modbus_strerror(errno));
        return 1;
    }
    map->tab_registers[ZW_REG_MAGIC] = ZW_REGMAP_MAGIC;
    map->tab_registers[ZW_REG_VERSION] = ZW_REGMAP_VERSION;
    int listener = modbus_tcp_listen(ctx, 1);
    if (listener < 0) {
        fprintf(stderr, "bench_plain_server: cannot listen on 127.0.0.1:%d: %s\n", port,
                modbus_strerror(errno));
        return 1;
    }
    fprintf(stderr, "bench_plain_server: listening on 127.0.0.1:%d\n", port);

    uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
    for (;;) {
        int conn = modbus_tcp_accept(ctx, &listener);
        if (conn < 0) {
            if (errno == EINTR) continue;
            fprintf(stderr, "bench_plain_server: accept: %s\n", modbus_strerror(errno));
            break;
        }
        for (;;) {
            int rc = modbus_receive(ctx, query);
            if (rc > 0) {
                modbus_reply(ctx, query, rc, map);
            } else if (rc == -1) {
                break; /* client gone */
            }
        }
        close(conn);
        modbus_set_socket(ctx, -1);
    }
    close(listener);
    modbus_mapping_free(map);
    modbus_free(ctx);
    return 0;
}
