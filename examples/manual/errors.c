/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* X4Step manual, chapter 4.2: the example of the error codes (chapter 4.1): every documented error in its situation, as printed; only
 * main() gets its int and the port is LPT1 (the manual uses LPT2; the
 * test bench has one port). */
#include <stdio.h>
#include "x4step.h"

static int failed;

static void expect(const char *what, int got, int want)
{
    printf("%s %s (%d)\n", got == want ? "PASS" : "FAIL", what, got);
    failed |= got != want;
}

int main(void)
{
    char many[22];
    int i;

    expect("X4Load before X4Init", X4Load(1, 0, 0, 0, 1000, 0), X4ErrInitNotDone);
    expect("X4Start before X4Init", X4Start(), X4ErrInitNotDone);
    expect("X4ReInit before X4Init", X4ReInit(), X4ErrInitNotDone);
    expect("X4Init(0)", X4Init(0), X4ErrParamFail);
    expect("X4Init(5)", X4Init(5), X4ErrParamFail);
    expect("X4Init(LPT4) without port", X4Init(LPT4), X4ErrLPTNotFound);
    expect("X4Init(LPT1)", X4Init(LPT1), X4NoErr);
    expect("no steps", X4Load(0, 0, 0, 0, 1000, 50), X4ErrNoSteps);
    expect("20001 Hz", X4Load(1, 0, 0, 0, 20001, 50), X4ErrFreqTooHigh);
    expect("9 Hz", X4Load(1, 0, 0, 0, 9, 0), X4ErrFreqTooLow);
    expect("1001 ms", X4Load(1, 0, 0, 0, 2000, 1001), X4ErrRampTooHigh);
    expect("10 Hz, 50 ms", X4Load(1, 0, 0, 0, 10, 50), X4ErrRampFreq);
    expect("16777217 steps", X4Load(0, 16777217, 0, 0, 1000, 0), X4ErrStepsTooHigh);
    expect("-2^31 steps", X4Load(0, 0, 0, -2147483647L - 1, 1000, 0), X4ErrStepsTooHigh);
    expect("X4Start nothing loaded", X4Start(), X4ErrNotLoaded);
    expect("X4Brake nothing running", X4Brake(), X4ErrNotActive);
    expect("X4Stop nothing running", X4Stop(), X4ErrNotActive);
    expect("X4MovePos axis 0", X4MovePos(0, 1000, 50), X4ErrParamFail);
    expect("X4MoveNeg axis 5", X4MoveNeg(5, 1000, 50), X4ErrParamFail);
    expect("X4SetOut(0)", X4SetOut(0), X4ErrParamFail);
    expect("X4SetOut(5)", X4SetOut(5), X4ErrParamFail);
    for (i = 0; i < 21; i++)
        many[i] = (char)(i + 2);
    many[21] = 0;
    expect("21 brake codes", X4BrakeCodes(many), X4ErrParamFail);
    expect("X4Load", X4Load(100, 0, 0, 0, 1000, 0), X4NoErr);
    expect("X4Load twice", X4Load(100, 0, 0, 0, 1000, 0), X4ErrIsLoaded);
    expect("X4MovePos while loaded", X4MovePos(1, 1000, 50), X4ErrIsLoaded);
    expect("X4Start", X4Start(), X4NoErr);
    expect("X4MovePos while active", X4MovePos(1, 1000, 50), X4ErrIsActive);
    expect("X4Load (preload)", X4Load(-100, 0, 0, 0, 1000, 0), X4NoErr);
    expect("X4Start while active", X4Start(), X4ErrIsActive);
    expect("X4GetSteps(0)", (int)X4GetSteps(0), 0);
    expect("X4GetSteps(5)", (int)X4GetSteps(5), 0);
    while (X4GetState())
        ;
    expect("steps after the move", (int)X4GetSteps(1), 100);
    expect("X4Start preloaded", X4Start(), X4NoErr);
    while (X4GetState())
        ;
    expect("steps after the second move", (int)X4GetSteps(1), -100);
    expect("X4ReInit", X4ReInit(), X4NoErr);
    expect("X4ReInit twice", X4ReInit(), X4ErrInitNotDone);
    printf("SEG 100 0 0 0\nSEG -100 0 0 0\n");
    return failed;
}
