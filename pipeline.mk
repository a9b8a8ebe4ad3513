# The reconstruction pipeline as a Makefile: every stage a program, every intermediate a
# file in $(RUN_DIR), each rerun only when its inputs or its parameters change.
#
#   make -f pipeline.mk                       # default synthetic scene, whole pipeline
#   make -f pipeline.mk DATA=dinoRing         # a Middlebury set
#   make -f pipeline.mk DATA=dinoRing T=0.5 LAMBDA=0.5 cut1
#   make -f pipeline.mk DATA_DIR=/photos/ws   # a COLMAP workspace (images/ + sparse/)
#   make -f pipeline.mk help                  # targets, variables and parameters
#
# Parameters given on the command line (T=0.5, LAMBDA=4, ...: see `help`) are tracked:
# changing one reruns exactly the stages that use it and those after them.

SHELL := /bin/bash
.DEFAULT_GOAL := all
.SUFFIXES:
.DELETE_ON_ERROR:
MAKEFLAGS += --no-builtin-rules

ROOT      := $(patsubst %/,%,$(dir $(abspath $(lastword $(MAKEFILE_LIST)))))
BUILD_DIR ?= $(ROOT)/build
BIN       := $(BUILD_DIR)/bin
# The default scene is rendered by the project itself (no network needed).
DATA      ?= synth-torus
# Middlebury sets: a sibling shared/data/middlebury folder when there is one, else data/.
DATA_DIR  ?= $(firstword $(wildcard $(ROOT)/../shared/data/middlebury) $(ROOT)/data)
# DATA_DIR may also be ONE COLMAP workspace (images/ + sparse/, docs/colmap.md): the run is
# then named after the folder unless DATA is given.
COLMAP_WS := $(if $(wildcard $(DATA_DIR)/sparse),$(patsubst %/,%,$(DATA_DIR)))
ifneq ($(COLMAP_WS),)
  ifneq ($(origin DATA),command line)
    DATA := $(notdir $(COLMAP_WS))
  endif
endif
SYNTH_DIR ?= $(ROOT)/data
RUN_DIR   ?= $(ROOT)/runs/$(DATA)
# Refinement levels: by default (auto) as many as bring the finest cells to TARGET_PIXELS
# (refine.target_pixels) in every view, computed from the scene once it is ingested
# (`bcc-init --print-levels`, kept in $(RUN_DIR)/levels.mk), so that 640 x 480 and
# 1600 x 1200 photos share one default (dinoRing: 3 levels, cells of about 4 px).
# LEVELS=N fixes the number (dinoRing: LEVELS=4 gives about 2 px but takes several times longer).
LEVELS    ?= auto
# Optional JSON file of parameter overrides; a dataset's examples/params/<DATA>.json by default.
PARAMS    ?= $(wildcard $(ROOT)/examples/params/$(DATA).json)
QUIET     ?=
# Every stage appends one JSON line (seconds, peak memory, summary) to this log.
export TETMVS_LOG := $(RUN_DIR)/stages.jsonl
# glibc's malloc asks for transparent huge pages for the stages' large arrays (a third less
# time on 4 M-cell meshes: docs/architecture.md); a value of the tunable already set is kept.
ifeq ($(findstring glibc.malloc.hugetlb,$(GLIBC_TUNABLES)),)
export GLIBC_TUNABLES := $(if $(GLIBC_TUNABLES),$(GLIBC_TUNABLES):)glibc.malloc.hugetlb=1
endif
STAGE_FLAGS := $(if $(QUIET),--quiet) $(if $(PARAMS),--params $(PARAMS))

ifneq ($(COLMAP_WS),)
  DATASET := $(COLMAP_WS)
  GT      := $(wildcard $(DATASET)/gt.ply)
else ifneq ($(filter synth-%,$(DATA)),)
  DATASET := $(SYNTH_DIR)/$(DATA)
  GT      := $(DATASET)/gt.ply
else
  DATASET := $(DATA_DIR)/$(DATA)
  GT      := $(wildcard $(DATASET)/gt.ply)
endif

PROGRAMS := $(notdir $(wildcard $(ROOT)/stages/*))
has = $(filter $(1),$(PROGRAMS))
MIDDLEBURY := dinoRing templeRing dinoSparseRing templeSparseRing

# --- the variables, checked before anything is made ----------------------------------------
ifeq ($(filter help help-all clean,$(MAKECMDGOALS)),)
ifneq ($(words $(LEVELS)) $(filter $(LEVELS),auto 1 2 3 4 5 6 7 8 9 10 11 12),1 $(LEVELS))
$(error LEVELS='$(LEVELS)': give the number of refinement levels, a whole number from 1 to 12, or auto)
endif
endif
ifneq ($(words $(DATA)) $(words $(RUN_DIR)),1 1)
$(error DATA='$(DATA)', RUN_DIR='$(RUN_DIR)': each must be one word (no spaces))
endif
# RUN_DIR is written into and `clean` removes it: never the source tree, a folder that
# holds it, or the home folder
RUN_ABS := $(abspath $(RUN_DIR))
ifneq ($(or $(filter / $(abspath $(HOME)),$(RUN_ABS)),$(filter $(RUN_ABS)/%,$(ROOT)/)),)
$(error RUN_DIR=$(RUN_DIR) is $(RUN_ABS), which holds the sources or is the home folder; give a run folder of its own)
endif
ifeq ($(COLMAP_WS)$(filter synth-%,$(DATA))$(filter $(DATA),$(MIDDLEBURY))$(filter help help-all clean,$(MAKECMDGOALS)),)
ifeq ($(wildcard $(DATASET)/.),)
$(error DATA=$(DATA): no dataset folder $(DATASET) (give synth-<object>, one of $(MIDDLEBURY), a folder under DATA_DIR=$(DATA_DIR), or DATA_DIR=<COLMAP workspace>))
endif
endif

# --- parameters: make variable -> key -> stages (generated from params/defaults.json) --
# params.mk is made by the build; the rule below builds first on a fresh clone, and make then
# re-reads this file with it (without it, LAMBDA=... on the first run would be ignored).
-include $(BUILD_DIR)/params.mk
ifneq ($(MAKECMDGOALS),clean)
$(BUILD_DIR)/params.mk: $(ROOT)/params/defaults.json $(ROOT)/cmake/embed_json.cmake
	@BUILD_DIR=$(BUILD_DIR) bash $(ROOT)/scripts/build.sh && touch $@
endif
# --set arguments of stage $(1) from the variables given on the command line
set_args = $(strip $(foreach v,$(MAKE_PARAMS),$(if $(and $(filter $(1),$(PARAM_$(v)_STAGES)),$(filter command line,$(origin $(v)))),--set $(PARAM_$(v)_KEY)=$($(v)))))
STAMPS := $(RUN_DIR)/.params
# A stage's stamp file holds its parameter arguments; it is rewritten (here, when the
# makefile is read) only when they change, so its time stamp tells make exactly when the
# stage's parameters last changed. Done at parse time so that `make -n` is truthful.
ALL_STAGES := ingest bcc-init photoconsist refine label cut silhouette-fix deform evaluate
# From a PARAMS file, only the entries of the stage's own parameters count (sorted
# "key": value text): editing a label parameter there reruns label and what follows, not
# photoconsist; a comment or another stage's key changes nothing.
empty :=
space := $(empty) $(empty)
stage_keys = $(foreach v,$(MAKE_PARAMS),$(if $(filter $(1),$(PARAM_$(v)_STAGES)),$(subst .,\.,$(PARAM_$(v)_KEY))))
params_for = $(if $(and $(PARAMS),$(call stage_keys,$(1))),$(shell tr -d '\n' < '$(PARAMS)' | grep -oE '"($(subst $(space),|,$(strip $(call stage_keys,$(1)))))" *: *("[^"]*"|[^,}]*)' | tr -d ' ' | LC_ALL=C sort | tr '\n' ' '))
# The stage's built-in defaults count too: a changed default in params/defaults.json reruns
# the stages that use it (and what follows), as a changed command-line value does.
# (stripped: the empty words of the other stages' parameters must not count, or adding a
# parameter to any stage would rerun every stage of every run)
stage_defaults = $(strip $(foreach v,$(MAKE_PARAMS),$(if $(filter $(1),$(PARAM_$(v)_STAGES)),$(PARAM_$(v)_KEY)=$(PARAM_$(v)_DEFAULT))))
stamp_text = $(call set_args,$(1)) $(STAGE_FLAGS) $(subst ','"'"',$(call params_for,$(1)) defaults: $(call stage_defaults,$(1)))
# A dry run (make -n) must not touch the run: it compares against a copy of the stamps.
# (MAKEFLAGS's first word holds the single-letter flags; without any it is pipeline.mk's own
# --no-builtin-rules, whose n is not a dry run.)
ifneq ($(findstring n,$(filter-out --%,$(firstword -$(MAKEFLAGS)))),)
STAMPS := $(shell d='$(RUN_DIR)/.params-dry'; rm -rf "$$d"; mkdir -p "$$d"; cp -p '$(RUN_DIR)/.params/'*.args "$$d"/ 2>/dev/null; echo "$$d")
endif
ifeq ($(filter help help-all clean,$(MAKECMDGOALS)),)
_stamps := $(foreach s,$(ALL_STAGES),$(shell mkdir -p '$(STAMPS)' && printf '%s\n' '$(call stamp_text,$(s))' > '$(STAMPS)/$(s).args.new' && { cmp -s '$(STAMPS)/$(s).args.new' '$(STAMPS)/$(s).args' && rm -f '$(STAMPS)/$(s).args.new' || mv -f '$(STAMPS)/$(s).args.new' '$(STAMPS)/$(s).args'; }))
endif
args = $(call set_args,$(1)) $(STAGE_FLAGS)

# --- the number of levels (LEVELS=auto) ---------------------------------------------------
# levels.mk is made from the scene (after ingest) and make then re-reads this file with it,
# before any level is made. A dry run (make -n) makes nothing: it asks bcc-init about the
# ingested scene with the parameters given, else (no scene yet) plans 3 levels and says so.
ifeq ($(LEVELS)$(filter help help-all clean,$(MAKECMDGOALS)),auto)
LEVELS_MK := $(RUN_DIR)/levels.mk
ifeq ($(findstring n,$(filter-out --%,$(firstword -$(MAKEFLAGS)))),)
include $(LEVELS_MK)
$(LEVELS_MK): $(RUN_DIR)/scene.h5 $(STAMPS)/bcc-init.args | programs
	@n=$$(TETMVS_LOG= $(BIN)/bcc-init --scene $< --print-levels --quiet $(call args,bcc-init)) && \
	  if [ "$$n" -lt 1 ]; then n=1; elif [ "$$n" -gt 12 ]; then \
	    echo "pipeline.mk: $$n levels would reach refine.target_pixels, more than 12: give LEVELS or a larger TARGET_PIXELS" >&2; exit 1; fi && \
	  echo "LEVELS_AUTO := $$n" > $@.tmp && mv -f $@.tmp $@ && \
	  $(if $(QUIET),true,echo "pipeline.mk: LEVELS=$$n (finest cells of at most refine.target_pixels in every view)")
else
LEVELS_AUTO := $(if $(wildcard $(RUN_DIR)/scene.h5),$(shell TETMVS_LOG= '$(BIN)/bcc-init' --scene '$(RUN_DIR)/scene.h5' --print-levels --quiet $(call args,bcc-init) 2>/dev/null))
ifeq ($(LEVELS_AUTO),)
LEVELS_AUTO := 3
$(info pipeline.mk: the number of levels follows from the scene, not yet ingested: this plan shows 3)
endif
endif
endif
# (LEVELS_AUTO comes from levels.mk, not LEVELS, which a command line's LEVELS=auto would
# hold fixed; 1 before levels.mk exists: make re-reads this file once it is made, before
# making any level)
LEVEL_COUNT := $(if $(filter auto,$(LEVELS)),$(if $(filter-out 0,$(LEVELS_AUTO)),$(LEVELS_AUTO),1),$(LEVELS))

# --- programs ---------------------------------------------------------------------------
.PHONY: programs
programs:
	@BUILD_DIR=$(BUILD_DIR) bash $(ROOT)/scripts/build.sh
$(BIN)/%: | programs ;

# --- data ---------------------------------------------------------------------------------
$(DATA_DIR)/%/.present:
	@bash $(ROOT)/scripts/fetch_middlebury.sh $* $(DATA_DIR)
# Synthetic scenes use dinoRing's 48 cameras when the set is at hand, else a generated ring.
SYNTH_CAMERAS ?= $(firstword $(wildcard $(DATA_DIR)/dinoRing/dinoR_par.txt) ring)
SYNTH_FLAGS   ?=
# The scene is rendered again when what it is made from changes (SYNTH_CAMERAS, SYNTH_FLAGS,
# SYNTH_TEXTURE and the other synth parameters): a stamp beside its folder keeps them, rewritten
# only when they change (a dry run compares against a copy, as the stages' stamps do).
ifneq ($(filter synth-%,$(DATA)),)
ifeq ($(filter help help-all clean,$(MAKECMDGOALS)),)
SYNTH_STAMP := $(SYNTH_DIR)/.$(DATA).args
ifneq ($(findstring n,$(filter-out --%,$(firstword -$(MAKEFLAGS)))),)
SYNTH_STAMP := $(shell cp -p '$(SYNTH_STAMP)' '$(STAMPS)/synth.args' 2>/dev/null; echo '$(STAMPS)/synth.args')
endif
_synth_stamp := $(shell mkdir -p '$(SYNTH_DIR)' && printf '%s\n' '--cameras $(SYNTH_CAMERAS) $(SYNTH_FLAGS) $(subst ','"'"',$(call set_args,synth) $(call params_for,synth))' > '$(SYNTH_STAMP).$$$$' && { cmp -s '$(SYNTH_STAMP).$$$$' '$(SYNTH_STAMP)' && rm -f '$(SYNTH_STAMP).$$$$' || mv -f '$(SYNTH_STAMP).$$$$' '$(SYNTH_STAMP)'; })
$(DATASET)/gt.ply: $(SYNTH_STAMP)
endif
endif
$(SYNTH_DIR)/synth-%/gt.ply: | programs
	$(BIN)/synth --object $* --cameras $(SYNTH_CAMERAS) --out $(SYNTH_DIR)/synth-$* $(SYNTH_FLAGS) $(call args,synth)

ifneq ($(COLMAP_WS),)
DATASET_READY :=
else ifneq ($(filter synth-%,$(DATA)),)
DATASET_READY := $(GT)
else ifneq ($(filter $(DATA),$(MIDDLEBURY)),)
DATASET_READY := $(if $(wildcard $(DATASET)/*_par.txt),,$(DATA_DIR)/$(DATA)/.present)
else
DATASET_READY :=
endif

# --- damaged intermediates ---------------------------------------------------------------
# A file of the run damaged after it was made (truncated in place, overwritten) is newer
# than its inputs, so make would take it as done and every later stage would fail on it:
# `validate` names those of the files the stages (and the report) read that cannot be opened
# as what they are, and they are made again with what follows them. cut1.h5, a side file of
# cut1.ply, is made again by its stage. (Files nothing reads, such as points.ply or
# deform.h5, are left as they are.)
RUN_FILES := $(wildcard $(addprefix $(RUN_DIR)/,scene.h5 mesh_*.h5 pc_*.h5 scores.h5 labels.h5 silfix.h5 cut1.h5 \
  cut1.ply cut2.ply final.ply eval_*.json))
ifneq ($(and $(RUN_FILES),$(wildcard $(BIN)/validate),$(filter-out help help-all clean,$(or $(MAKECMDGOALS),all))),)
DAMAGED := $(shell TETMVS_LOG= '$(BIN)/validate' --names --quiet $(RUN_FILES) 2>/dev/null)
endif
target_of = $(patsubst %/cut1.h5,%/cut1.ply,$(1))
ifneq ($(DAMAGED),)
$(info pipeline.mk: damaged, made again: $(notdir $(DAMAGED)))
$(sort $(call target_of,$(DAMAGED))): FORCE
endif
.PHONY: FORCE
FORCE:

# --- stages ------------------------------------------------------------------------------
.PHONY: all ingest mesh levels points cut1 cut2 final evaluate report help help-all clean
all: $(if $(call has,deform),final,$(if $(call has,silhouette-fix),cut2,$(if $(call has,cut),cut1,$(if $(call has,photoconsist),points,$(if $(call has,refine),levels,$(if $(call has,bcc-init),mesh,ingest)))))) $(if $(and $(call has,evaluate),$(GT),$(call has,cut)),evaluate)

ingest: $(RUN_DIR)/scene.h5
$(RUN_DIR)/scene.h5: $(DATASET_READY) $(STAMPS)/ingest.args | programs
	@mkdir -p $(@D)
	$(BIN)/ingest $(DATASET) -o $@ --contact-sheet $(RUN_DIR)/ingest_contact.png $(call args,ingest)

mesh: $(RUN_DIR)/mesh_0.h5
$(RUN_DIR)/mesh_0.h5: $(RUN_DIR)/scene.h5 $(STAMPS)/bcc-init.args | programs
	$(BIN)/bcc-init --scene $< --out $@ --slice-png $(RUN_DIR)/mesh_0_slice.png $(call args,bcc-init)

# Level i: photoconsist finds the crossing faces of mesh_i (pc_i.h5, with the face cache
# handed down from pc_{i-1}); refine red-green refines the active cells -> mesh_{i+1}.
NUMS := 0 1 2 3 4 5 6 7 8 9 10 11 12
LEVEL_IDS := $(wordlist 1,$(LEVEL_COUNT),$(NUMS))
prev = $(word $(1),$(NUMS))
define LEVEL_RULES
$(RUN_DIR)/pc_$(1).h5: $(RUN_DIR)/scene.h5 $(RUN_DIR)/mesh_$(1).h5 $(if $(filter 0,$(1)),,$(RUN_DIR)/pc_$(call prev,$(1)).h5) $(STAMPS)/photoconsist.args | programs
	$(BIN)/photoconsist --scene $(RUN_DIR)/scene.h5 --mesh $(RUN_DIR)/mesh_$(1).h5 --level $(1) $(if $(filter 0,$(1)),,--cache $(RUN_DIR)/pc_$(call prev,$(1)).h5) --out $$@ $$(call args,photoconsist)
$(RUN_DIR)/mesh_$(word $(shell echo $$(($(1)+2))),$(NUMS)).h5: $(RUN_DIR)/mesh_$(1).h5 $(RUN_DIR)/pc_$(1).h5 $(STAMPS)/refine.args | programs
	$(BIN)/refine --mesh $(RUN_DIR)/mesh_$(1).h5 --active $(RUN_DIR)/pc_$(1).h5 --out $$@ --slice-png $$(basename $$@)_slice.png $$(call args,refine)
endef
$(foreach i,$(LEVEL_IDS),$(eval $(call LEVEL_RULES,$(i))))
FINAL_MESH := $(RUN_DIR)/mesh_$(LEVEL_COUNT).h5
LAST_PC    := $(RUN_DIR)/pc_$(word $(LEVEL_COUNT),$(NUMS)).h5
levels: $(FINAL_MESH)

# Face scores of the final mesh (for the cut) and the quasi-dense points Q.
points: $(RUN_DIR)/scores.h5
$(RUN_DIR)/scores.h5: $(RUN_DIR)/scene.h5 $(FINAL_MESH) $(LAST_PC) $(STAMPS)/photoconsist.args | programs
	$(BIN)/photoconsist --scene $(RUN_DIR)/scene.h5 --mesh $(FINAL_MESH) --scores --cache $(LAST_PC) --out $@ --points-ply $(RUN_DIR)/points.ply $(call args,photoconsist)

$(RUN_DIR)/labels.h5: $(RUN_DIR)/scene.h5 $(FINAL_MESH) $(RUN_DIR)/scores.h5 $(STAMPS)/label.args | programs
	$(BIN)/label --scene $(RUN_DIR)/scene.h5 --mesh $(FINAL_MESH) --scores $(RUN_DIR)/scores.h5 --out $@ --slice-png $(RUN_DIR)/labels_slice.png $(call args,label)

cut1: $(RUN_DIR)/cut1.ply
$(RUN_DIR)/cut1.ply: $(FINAL_MESH) $(RUN_DIR)/scores.h5 $(RUN_DIR)/labels.h5 $(STAMPS)/cut.args | programs
	$(BIN)/cut --mesh $(FINAL_MESH) --scores $(RUN_DIR)/scores.h5 --labels $(RUN_DIR)/labels.h5 --out $(RUN_DIR)/cut1.h5 --ply $@ $(call args,cut)

$(RUN_DIR)/silfix.h5: $(RUN_DIR)/scene.h5 $(FINAL_MESH) $(RUN_DIR)/scores.h5 $(RUN_DIR)/labels.h5 $(RUN_DIR)/cut1.ply $(STAMPS)/silhouette-fix.args | programs
	$(BIN)/silhouette-fix --scene $(RUN_DIR)/scene.h5 --mesh $(FINAL_MESH) --scores $(RUN_DIR)/scores.h5 --labels $(RUN_DIR)/labels.h5 --cut $(RUN_DIR)/cut1.h5 --out $@ --png-dir $(RUN_DIR)/silfix $(call args,silhouette-fix)

cut2: $(RUN_DIR)/cut2.ply
$(RUN_DIR)/cut2.ply: $(FINAL_MESH) $(RUN_DIR)/scores.h5 $(RUN_DIR)/silfix.h5 $(STAMPS)/cut.args | programs
	$(BIN)/cut --mesh $(FINAL_MESH) --scores $(RUN_DIR)/scores.h5 --labels $(RUN_DIR)/silfix.h5 --out $(RUN_DIR)/cut2.h5 --ply $@ $(call args,cut)

final: $(RUN_DIR)/final.ply
$(RUN_DIR)/final.ply: $(RUN_DIR)/scene.h5 $(RUN_DIR)/cut2.ply $(STAMPS)/deform.args | programs
	$(BIN)/deform --scene $(RUN_DIR)/scene.h5 --mesh $(RUN_DIR)/cut2.ply --out $@ --stats $(RUN_DIR)/deform.h5 --png $(RUN_DIR)/final_views.png $(call args,deform)

# --- evaluation against ground truth (synthetic scenes; on a real set without gt.ply,
# `make evaluate` gives the mesh checks and the roughness only) -------------------------------
SURFACES := $(foreach s,cut1 cut2 final,$(if $(filter $(s),$(MAKECMDGOALS) all $(if $(call has,deform),final cut2 cut1,$(if $(call has,silhouette-fix),cut2 cut1,cut1))),$(s)))
evaluate: $(foreach s,$(SURFACES),$(RUN_DIR)/eval_$(s).json)
# On synthetic scenes the evaluation of a cut also counts the hard labels it was cut with
# that the ground truth contradicts (the "labels" object of schemas/evaluate.md).
LABELS_OF_cut1 := $(RUN_DIR)/labels.h5
LABELS_OF_cut2 := $(RUN_DIR)/silfix.h5
label_check = $(if $(and $(filter synth-%,$(DATA)),$(LABELS_OF_$(1))),--labels $(LABELS_OF_$(1)) --tetmesh $(FINAL_MESH))
$(RUN_DIR)/eval_%.json: $(RUN_DIR)/%.ply $(RUN_DIR)/scene.h5 $(GT) $(STAMPS)/evaluate.args | programs
	$(BIN)/evaluate --mesh $< --cameras $(RUN_DIR)/scene.h5 --out $@ $(if $(GT),--gt $(GT) --png $(RUN_DIR)/eval_$*.png $(call label_check,$*)) $(call args,evaluate)

# The report: a self-contained HTML page of whatever the run holds.
report: $(RUN_DIR)/report/index.html
$(RUN_DIR)/report/index.html: all | programs
	$(BIN)/report $(RUN_DIR) --out $@ $(if $(QUIET),--quiet)

# (only a folder this makefile ran in: it holds .params)
clean:
	@if [ -e '$(RUN_DIR)' ] && [ ! -d '$(RUN_DIR)/.params' ]; then \
	  echo "pipeline.mk: $(RUN_DIR) is not a run folder (no .params in it): not removed" >&2; exit 1; fi
	rm -rf '$(RUN_DIR)'

# Single-quote a string for the shell (paper values contain quotes).
shq = '$(subst ','\'',$(1))'

help:
	@echo "Targets:   all (default: every stage that exists), ingest, mesh, levels, points,"
	@echo "           cut1, cut2, final, evaluate, report, clean, help, help-all"
	@echo "Variables: DATA=$(DATA)  DATA_DIR=$(DATA_DIR)  RUN_DIR=$(RUN_DIR)"
	@echo "           LEVELS=$(LEVELS)  PARAMS=$(PARAMS)  QUIET=$(QUIET)  BUILD_DIR=$(BUILD_DIR)"
	@echo "           DATA: synth-<object> renders a synthetic scene; $(MIDDLEBURY) use DATA_DIR or download"
	@echo "           DATA_DIR=<COLMAP workspace> (images/ + sparse/) reconstructs it (docs/colmap.md)"
	@echo "Parameters (VAR=value on the command line; default, paper value, stages) of the paper and"
	@echo "its extensions; 'make -f pipeline.mk help-all' also lists the expert ones:"
	@$(call param_lines,$(foreach v,$(MAKE_PARAMS),$(if $(filter expert,$(PARAM_$(v)_TIER)),,$(v))))

help-all:
	@echo "Parameters (VAR=value on the command line; default, paper value, tier, stages):"
	@$(call param_lines,$(MAKE_PARAMS))

# One line per make variable in $(1): name, default, paper value, tier, stages.
param_lines = $(foreach v,$(1),d=$(call shq,$(PARAM_$(v)_DEFAULT)); if printf %g "$$d" >/dev/null 2>&1; then d=$$(printf %g "$$d"); fi; \
	  printf '  %-28s %-10s %-28s %-9s %s\n' '$(v)' "$$d" $(call shq,$(PARAM_$(v)_PAPER)) '$(PARAM_$(v)_TIER)' '$(PARAM_$(v)_STAGES)';)
