/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* X4Step manual, chapter 4.2: the example of X4Start, as printed; only
 * main() gets its int and the port is LPT1 (the manual uses LPT2; the
 * test bench has one port). */
#include "x4step.h"

int main(void)
{
    X4Init(1);           // X4Step starten und
                        // LPT2 verwenden
    X4Load(1000,0,0,0,1000,50); // Achse 1 laden
    X4Start();          // Positionierung starten
    while (X4GetState())
        ;               // warten, bis Positionierung
                        // beendet
    X4ReInit();         // X4Step beenden
    return 0;
}
