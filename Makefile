# The two commands of the README:
#   make run   installs what is missing, builds, and runs the main job on the default data
#   make test  installs what is missing, builds, and runs every test through ctest
BUILD ?= build
JOBS  ?= $(shell nproc)

.PHONY: run test deps build bench clean

deps:
	@scripts/install-deps.sh

build: deps
	@mkdir -p $(BUILD) && cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release > $(BUILD)/configure.log 2>&1 || (cat $(BUILD)/configure.log; exit 1)
	@cmake --build $(BUILD) -j $(JOBS)

run: build
	@$(MAKE) --no-print-directory -C pipelines run BIN=$(abspath $(BUILD))

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: build
	@$(MAKE) --no-print-directory -C bench run BIN=$(abspath $(BUILD))

clean:
	rm -rf $(BUILD)
