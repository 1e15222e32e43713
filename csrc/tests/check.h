/*
 * The check counter the host unit tests share: CHECK(cond, fmt, ...) counts a
 * pass, or counts a failure and prints where, the condition and the message.
 * Each test program includes it once and reports n_passed / n_failed.
 */
#ifndef WAKE_TESTS_CHECK_H
#define WAKE_TESTS_CHECK_H

#include <stdio.h>

static int n_passed = 0;
static int n_failed = 0;

#define CHECK(cond, ...)                                                        \
    do {                                                                        \
        if (cond) {                                                             \
            n_passed++;                                                         \
        } else {                                                                \
            n_failed++;                                                         \
            printf("FAIL %s:%d: %s -- ", __FILE__, __LINE__, #cond);            \
            printf(__VA_ARGS__);                                                \
            printf("\n");                                                       \
        }                                                                       \
    } while (0)

#endif /* WAKE_TESTS_CHECK_H */
