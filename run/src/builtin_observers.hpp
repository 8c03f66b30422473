#pragma once
// cobra's own observers of a run (observer.hpp), one per section of the `run` table: record,
// plots, summary, tracking, clearance, studio. Each owns its section's reading, its attach, its
// step and its report part; they are registered first, in this order (the report's rows and
// figures follow it). Private to cobra::run.

#include <string>
#include <vector>

#include "cobra/run/observer.hpp"

namespace cobra::core {
class Component;
}

namespace cobra::run {

// Registers them into `kinds` (the registry's first entries).
void addBuiltinObservers(std::vector<ObserverRegistry::Kind>& kinds);

// The kinds, one per file.
ObserverRegistry::Kind recordObserver();
ObserverRegistry::Kind plotsObserver();
ObserverRegistry::Kind summaryObserver();
ObserverRegistry::Kind trackingObserver();
ObserverRegistry::Kind clearanceObserver();
ObserverRegistry::Kind studioObserver();

// The figures of `run.plots` from the recording; `timeline` (lanes "<chart> chart") places the
// marks of the plots' paths. Figures and panels without data are left out.
std::vector<Figure> plotFigures(const std::vector<PlotSpec>& plots, const Recording& recording,
                                const std::vector<StateInterval>& timeline);
// Drops the panels without series and the figures without panels.
void dropEmpty(std::vector<Figure>& figures);

// The component of "Comp.member" when it has that operation (or property), else nullptr.
core::Component* ownerOf(const core::ComponentRegistry& refs, const std::string& path, bool operation);
// "member" of "Comp.member".
std::string memberOf(const std::string& path);
// "%8.3f s".
std::string seconds(double t);
bool startsWith(const std::string& text, const std::string& prefix);

}  // namespace cobra::run
