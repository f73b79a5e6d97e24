// SPDX-License-Identifier: GPL-2.0
// Drives a running CNCjs server as its web page does, through its
// socket.io API: opens PORT as a Grbl controller, loads PROGRAM, starts it,
// follows CNCjs's own controller state (Grbl:state) and workflow until the
// program has been sent and acknowledged and CNCjs has ended the run, then
// compares CNCjs's final machine position with EXPECTED.
// Runs with NODE_PATH at CNCjs's node_modules: its socket.io client (the
// server's version) and jsonwebtoken. run.sh starts it.
//
// Usage: node client.js URL SECRET PORT PROGRAM X,Y,Z[,A] TIMEOUT_S TOLERANCE
// Prints the states CNCjs saw and the final position; exit 0 when the run
// ended Idle at EXPECTED (each axis within TOLERANCE), 1 otherwise.
// X4_CNCJS_WORKFLOW=1: the hobbyist's day as CNCjs's buttons do it, before
// the run: home ($H), jog X+5 ($J=), probe Z (G38.2, its [PRB:...:1]),
// zero the work there (G10 L20 P1 X0 Y0 Z0); during the run a feed
// override (+10 %) and a feed hold with cycle start; EXPECTED is then the
// work position (WPos).
'use strict';
const fs = require('fs');
const path = require('path');
const io = require('socket.io-client');
const jwt = require('jsonwebtoken');

const [url, secret, port, program, expectedArg, timeoutArg, tolArg] = process.argv.slice(2);
if (!tolArg) {
    console.error('usage: client.js URL SECRET PORT PROGRAM X,Y,Z[,A] TIMEOUT_S TOLERANCE');
    process.exit(2);
}
const expected = expectedArg.split(',').map(Number);
const axes = ['x', 'y', 'z', 'a'].slice(0, expected.length);
const tolerance = Number(tolArg);
const workflow_mode = process.env.X4_CNCJS_WORKFLOW === '1';
const t0 = Date.now();
const stamp = () => ((Date.now() - t0) / 1000).toFixed(3).padStart(8);
const say = (...a) => console.log(stamp(), ...a);

// CNCjs's socket.io server takes a JWT signed with the .cncrc's secret;
// with no users in the .cncrc, any id and name pass.
const token = jwt.sign({ id: '', name: 'x4step-test' }, secret, { expiresIn: '1h' });
const socket = io.connect(url, { query: 'token=' + token, reconnection: false });

let phase = 'connect'; // connect, open (until Idle and $$), [steps], settle, load, running, finished
let lastState = null; // CNCjs's controller state, the last Grbl:state
const states = []; // activeState, in the order CNCjs reported them
let settings = 0;
let sender = null;
let workflow = '';
const problems = []; // error: and ALARM lines CNCjs read during the run
let ran = false; // the workflow has been running
let acked = false; // while running, CNCjs had every line acknowledged

function finish(code, why) {
    if (phase === 'finished') return;
    phase = 'finished';
    if (why) say(why);
    const st = lastState && lastState.status;
    console.log('states seen: ' + (states.join(' ') || '(none)'));
    if (st) {
        const fmt = (p) => axes.map((a) => p && p[a]).join(',');
        console.log(`final: activeState=${st.activeState} mpos=${fmt(st.mpos)} wpos=${fmt(st.wpos)}`);
    }
    if (sender) console.log(`sender: total=${sender.total} sent=${sender.sent} received=${sender.received}`);
    console.log(code === 0 ? 'PASS' : 'FAIL');
    // Close the port (CNCjs sends nothing for it), then leave.
    socket.emit('close', port, () => process.exit(code));
    setTimeout(() => process.exit(code), 2000);
}

function check() {
    if (!ran || workflow !== 'idle' || !acked) return;
    const st = (lastState && lastState.status) || {};
    const bad = [];
    if (st.activeState !== 'Idle') bad.push(`CNCjs's last state is ${st.activeState}, not Idle`);
    const pos = workflow_mode ? st.wpos : st.mpos;
    axes.forEach((a, i) => {
        const v = Number(pos && pos[a]);
        if (!(Math.abs(v - expected[i]) <= tolerance))
            bad.push(`${workflow_mode ? 'work' : 'machine'} ${a.toUpperCase()} ${pos && pos[a]}, expected ${expected[i]} (± ${tolerance})`);
    });
    if (workflow_mode && !(held && feed_override_seen === 110))
        bad.push(`no feed hold and 110 % override seen during the run (Ov ${feed_override_seen})`);
    problems.forEach((p) => bad.push('CNCjs read ' + p));
    finish(bad.length ? 1 : 0, bad.length ? bad.join('; ') : 'run ended Idle at the expected position');
}

setTimeout(() => finish(1, `timeout after ${timeoutArg} s in phase ${phase}`), Number(timeoutArg) * 1000);

socket.on('connect_error', (e) => finish(1, 'socket.io connect error: ' + e));
socket.on('error', (e) => finish(1, 'socket.io error: ' + JSON.stringify(e)));
socket.on('disconnect', (r) => phase !== 'finished' && finish(1, 'CNCjs disconnected: ' + r));

// The server's greeting carries the .cncrc's ports: the pty must be there.
socket.on('startup', (data) => {
    const listed = (data.ports || []).some((p) => p.path === port);
    say(`connected; controllers ${data.loadedControllers}; .cncrc ports ${JSON.stringify(data.ports)}`);
    if (!listed) return finish(1, `${port} is not among CNCjs's configured ports`);
    phase = 'open';
    socket.emit('open', port, { controllerType: 'Grbl', baudrate: 115200 }, (err) => {
        if (err) return finish(1, 'CNCjs could not open ' + port + ': ' + err);
        say('CNCjs opened ' + port + ' as Grbl');
    });
});

socket.on('serialport:error', (e) => finish(1, 'serialport:error ' + JSON.stringify(e)));
socket.on('serialport:close', () => phase !== 'finished' && finish(1, 'CNCjs closed the port'));
socket.on('serialport:read', (line) => {
    if (/^(error|ALARM):/.test(line) && (ran || step > 0)) problems.push(line);
    if (/^\[PRB:.*:1\]$/.test(line)) probed = line;
    if (!/^\$\d+=/.test(line)) say('read: ' + line);
});
socket.on('Grbl:settings', (s) => {
    const n = Object.keys((s && s.settings) || {}).length;
    if (n !== settings) say(`CNCjs holds ${n} settings from $$` + (s.version ? `, version ${s.version}` : ''));
    settings = n;
    ready();
});
socket.on('sender:status', (s) => {
    // Stopping the workflow rewinds the sender: keep the counts of the run.
    if (ran && s.received === 0 && acked) return;
    sender = s;
    if (ran && s.total > 0 && s.received >= s.total) acked = true;
    check();
});
socket.on('workflow:state', (w) => {
    if (w !== workflow) say('workflow: ' + w);
    workflow = w;
    if (w === 'running') ran = true;
    check();
});

socket.on('Grbl:state', (state) => {
    lastState = state;
    const st = state.status || {};
    if (st.activeState && st.activeState !== states[states.length - 1]) {
        states.push(st.activeState);
        say(`state ${st.activeState} mpos ${JSON.stringify(st.mpos)}`);
    }
    ready();
    during_run(st);
    check();
});

// The workflow's steps before the run: each a command and the state (and
// what else) that ends it.
let step = 0;
let probed = null;
let held = false;
let overridden = false;
const near = (p, a, v) => Math.abs(Number(p && p[a]) - v) <= tolerance;
const steps = [
    { say: 'home ($H, CNCjs homing)', run: () => socket.emit('command', port, 'homing'),
      done: (st) => st.activeState === 'Idle' && near(st.mpos, 'x', 3) && near(st.mpos, 'z', -1) },
    { say: 'jog X+5 ($J=)', run: () => socket.emit('command', port, 'gcode', '$J=G91 X5 F600'),
      done: (st) => st.activeState === 'Idle' && near(st.mpos, 'x', 8) },
    { say: 'probe Z (G38.2)', run: () => socket.emit('command', port, 'gcode', 'G38.2 Z-20 F100'),
      done: (st) => st.activeState === 'Idle' && probed !== null },
    { say: 'zero the work here (G10 L20)', run: () => socket.emit('command', port, 'gcode', 'G10 L20 P1 X0 Y0 Z0'),
      done: (st) => st.activeState === 'Idle' && near(st.wpos, 'x', 0) && near(st.wpos, 'z', 0) },
];
function next_step(st) {
    if (phase !== 'steps') return false;
    if (step > 0 && !steps[step - 1].done(st)) return true;
    if (step === steps.length) {
        say(`workflow steps done: probe ${probed}`);
        phase = 'open';
        return false;
    }
    say('step: ' + steps[step].say);
    steps[step++].run();
    return true;
}

// During the run: +10 % feed override, then a hold and, once held, cycle start.
let feed_override_seen = 0;
function during_run(st) {
    if (!workflow_mode || phase !== 'running' || st.activeState === undefined) return;
    if (st.ov && overridden) feed_override_seen = Math.max(feed_override_seen, Number(st.ov[0]));
    if (st.activeState === 'Run' && !overridden) {
        overridden = true;
        say('feed override +10 %');
        socket.emit('command', port, 'feedOverride', 10);
        setTimeout(() => { say('feed hold'); socket.emit('command', port, 'feedhold'); }, 500);
    } else if (st.activeState === 'Hold' && !held) {  // CNCjs: activeState Hold, subState 0
        held = true;
        setTimeout(() => { say('cycle start'); socket.emit('command', port, 'cyclestart'); }, 500);
    }
}

// CNCjs is connected once its Grbl controller has had a status report
// (Idle) and the settings it asked for with $$: then, a second later (the
// answers to CNCjs's first queries all in), load and start the program as
// a user would.
function ready() {
    const st = (lastState && lastState.status) || {};
    if (workflow_mode && phase === 'open' && step === 0 && settings > 0 &&
        (st.activeState === 'Alarm' || st.activeState === 'Idle'))
        phase = 'steps';
    if (next_step(st)) return;
    if (phase !== 'open' || st.activeState !== 'Idle' || settings === 0) return;
    phase = 'settle';
    setTimeout(() => {
        phase = 'load';
        const gcode = fs.readFileSync(program, 'utf8');
        socket.emit('command', port, 'gcode:load', path.basename(program), gcode, {}, (err, s) => {
            if (err) return finish(1, 'gcode:load: ' + err);
            say(`loaded ${path.basename(program)}: ${s.total} lines`);
            phase = 'running';
            socket.emit('command', port, 'gcode:start');
        });
    }, 1000);
}
