//! Finds PETSc and its MPI with pkg-config (Debian: `apt-get install
//! petsc-dev pkg-config`; elsewhere set PKG_CONFIG_PATH to
//! $PETSC_DIR/$PETSC_ARCH/lib/pkgconfig) and compiles the C side of the
//! layer (src/shim.c) against their headers.

fn main() {
    println!("cargo:rerun-if-changed=src/shim.c");
    let petsc = match pkg_config::Config::new().atleast_version("3.18").cargo_metadata(false).probe("petsc") {
        Ok(library) => library,
        Err(e) => {
            eprintln!(
                "seam-petsc: PETSc (≥ 3.18) was not found by pkg-config: {e}\n\
                 Install it (Debian/Ubuntu: apt-get install petsc-dev pkg-config) or set PKG_CONFIG_PATH \
                 to the directory of PETSc.pc ($PETSC_DIR/$PETSC_ARCH/lib/pkgconfig)."
            );
            std::process::exit(1);
        }
    };
    // PETSc's headers include mpi.h, which PETSc itself finds through its
    // mpicc wrapper: take MPI's paths from pkg-config (Open MPI: "mpi").
    let mpi = ["mpi-c", "mpi", "ompi-c"]
        .iter()
        .find_map(|name| pkg_config::Config::new().cargo_metadata(false).probe(name).ok());
    let mut shim = cc::Build::new();
    shim.file("src/shim.c").warnings(true).extra_warnings(true).flag_if_supported("-Wno-unused-parameter");
    for path in &petsc.include_paths {
        shim.include(path);
    }
    for path in mpi.iter().flat_map(|m| &m.include_paths) {
        shim.include(path);
    }
    for (name, value) in &petsc.defines {
        shim.define(name, value.as_deref());
    }
    shim.compile("seam_petsc_shim");
    // The shim's symbols refer to PETSc's: link it after the shim.
    for library in std::iter::once(&petsc).chain(&mpi) {
        for path in &library.link_paths {
            println!("cargo:rustc-link-search=native={}", path.display());
        }
        for lib in &library.libs {
            println!("cargo:rustc-link-lib={lib}");
        }
    }
}
