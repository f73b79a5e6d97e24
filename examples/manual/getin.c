/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* X4Step manual, chapter 4.2: the example of X4GetIn, as printed; only
 * main() gets its int and the port is LPT1 (the manual uses LPT2; the
 * test bench has one port). */
#include <stdio.h>
#include "x4step.h"

int main(void)
{
    X4Init(1);           // X4Step starten und
    X4MovePos(1,1000,50); // LPT2 verwenden
                        // Achse 1 endlos fahren mit
                        // 1000 Hz und 50 ms Rampe
    while ((X4GetIn() & 0x01) == 0)
        ;               // warten auf Pin 15 HIGH
    X4Brake();          // dann stoppen
    printf("inputs 0x%02x\n", X4GetIn());
    X4ReInit();         // X4Step beenden
    return 0;
}
