/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* X4Step manual, chapter 4.2: the example of X4SetOut, as printed; only
 * main() gets its int and the port is LPT1 (the manual uses LPT2; the
 * test bench has one port). */
#include "x4step.h"

int main(void)
{
    X4Init(1);           // X4Step starten und
                        // LPT2 verwenden
    X4SetOut(SIGNAL1ON); // Pin 1 HIGH schalten
    X4MovePos(1,1000,50);
                        // Achse 1 endlos fahren mit
                        // 1000 Hz und 50 ms Rampe
    while (X4GetState()) // warten, bis mit ESC
        ;               // abgebrochen wird
    X4SetOut(SIGNAL1OFF);
                        // Pin 1 wieder LOW
    X4ReInit();        // X4Step beenden
    return 0;
}
