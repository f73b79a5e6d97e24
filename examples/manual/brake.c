/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* X4Step manual, chapter 4.2: the example of X4Brake (its loop's +i read as ++i, and 30000 made 300000000 so that the axis moves before the brake), as printed; only
 * main() gets its int and the port is LPT1 (the manual uses LPT2; the
 * test bench has one port). */
#include <stdio.h>
#include "x4step.h"

volatile long i;

int main(void)
{
    // X4Step starten und
    X4Init(1);           // LPT2 verwenden
    X4MovePos(1,1000,50);
                        // Achse 1 endlos fahren mit
                        // 1000 Hz und 50 ms Rampe
    for (i=0;i<300000000;++i) // warten
        ;
    X4Brake();          // Fahrt abbrechen
    while (X4GetState())
        // warten bis Achse steht
        ;
    i = X4GetSteps(1);
    X4ReInit();        // gefahrene Schritte lesen
                        // X4Step beenden
    printf("SEG %ld 0 0 0 braked\n", i);
    return 0;
}
