/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* X4Step manual, chapter 4.2: the example of X4ClearTimer and X4GetTimer, as printed; only
 * main() gets its int and the port is LPT1 (the manual uses LPT2; the
 * test bench has one port). */
#include <stdio.h>
#include "x4step.h"

int main(void)
{
    X4Init(1);           // X4Step starten und
                        // LPT2 verwenden
    X4MovePos(1,1000,50);
                        // Achse 1 endlos fahren mit
                        // 1000 Hz und 50 ms Rampe
    X4ClearTimer();     // Timer löschen
    while (X4GetTimer() < 500)
        ;               // 500 ms warten
    X4Brake();          // Fahrt abbrechen
    while (X4GetState())
        ;
    printf("timer %ld ms\nSEG %ld 0 0 0 braked\n", X4GetTimer(), X4GetSteps(1));
    X4ReInit();         // X4Step beenden
    return 0;
}
