/* A module process that shakes hands correctly and then writes a frame whose
 * length prefix is far over the limit, for the malformed-frame test. It talks
 * to the socket directly (no hal-sim) as a broken or hostile client would. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "chainsim_protocol.h"

static int read_full(int fd, uint8_t *b, size_t n) {
    while (n) {
        ssize_t r = read(fd, b, n);
        if (r <= 0) return -1;
        b += r;
        n -= (size_t)r;
    }
    return 0;
}

int main(void) {
    const char *path = getenv("CHAINSIM_SOCKET");
    const char *idx = getenv("CHAINSIM_MODULE_INDEX");
    const char *type = getenv("CHAINSIM_MODULE_TYPE");
    if (!path || !idx || !type) return 2;
    int fd = socket(AF_UNIX, SOCK_STREAM, 0);
    struct sockaddr_un a;
    memset(&a, 0, sizeof a);
    a.sun_family = AF_UNIX;
    strncpy(a.sun_path, path, sizeof a.sun_path - 1);
    if (connect(fd, (struct sockaddr *)&a, sizeof a) != 0) return 3;
    static cs_msg m;
    m.type = CS_MSG_HELLO;
    m.u.hello.magic = CS_MAGIC;
    m.u.hello.version = CS_VERSION;
    m.u.hello.module_index = (uint16_t)atoi(idx);
    m.u.hello.pid = (uint32_t)getpid();
    strncpy(m.u.hello.type, type, CS_TYPE_NAME_MAX - 1);
    static uint8_t buf[4 + CS_BODY_MAX];
    size_t n = cs_encode(&m, buf, sizeof buf, NULL);
    if (write(fd, buf, n) != (ssize_t)n) return 3;
    /* WELCOME, then the first TICK_BEGIN */
    for (int k = 0; k < 2; ++k) {
        uint32_t len = 0;
        if (read_full(fd, buf, 4) || cs_body_length(buf, &len, NULL) != CS_OK || read_full(fd, buf, len)) return 3;
    }
    const uint8_t garbage[] = {0xff, 0xff, 0xff, 0x7f, 0xde, 0xad, 0xbe, 0xef};
    if (write(fd, garbage, sizeof garbage) != (ssize_t)sizeof garbage) return 3;
    pause(); /* the server must end us */
    return 0;
}
