#pragma once
// The Boost.MSM peer of statechart_bench.cpp, behind plain functions: it is compiled as C++17
// (Boost 1.74's MSM does not compile as C++20).

struct MsmPeer;
MsmPeer* msmCreate();
/// Dispatches event 0 (A -> B), 1 (B -> Slow) or 2 (Slow -> A), each with a guard returning true.
void msmDispatch(MsmPeer* machine, int event);
void msmDestroy(MsmPeer* machine);
