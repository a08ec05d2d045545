#pragma once
// The sections of docs/paper-reproduction.md, in the order write_markdown puts them.

#include <sstream>

#include "tools/reproduce_paper/output.h"
#include "tools/reproduce_paper/results.h"

namespace rollgap::tools::paper {

// Title, what was run and how to rerun it.
void md_introduction(std::ostringstream& md, const Results& R, const Output& out);
// One row per figure: the paper's claim, what the model gives, the verdict.
void md_summary(std::ostringstream& md, const Results& R);
// What sets the critical speed at the defaults: the crossing mode followed over speed.
void md_critical_speed(std::ostringstream& md, const Results& R);
// Figs. 8-12, one section each.
void md_sweep_figures(std::ostringstream& md, const Results& R, const Output& out);
// Fig. 13.
void md_amplitude_figure(std::ostringstream& md, const Results& R, const Output& out);
// Figs. 14-15.
void md_cycle_figures(std::ostringstream& md, const Results& R, const Output& out);
// The paper's inlet film against the frame-corrected (eulerian) one.
void md_film_comparison(std::ostringstream& md, const Results& R, const Output& out);
// The boundary-friction variant (m_a < 1): force over speed and the verdicts per variant.
void md_boundary_friction(std::ostringstream& md, const Results& R, const Output& out);
// Notes for the core and the list of files.
void md_notes_and_files(std::ostringstream& md, const Output& out);

// The mechanism paragraph of one of Figs. 8-12.
std::string md_figure_mechanism(const SweepFigure& fig, const Results& R, std::size_t index);

}  // namespace rollgap::tools::paper
