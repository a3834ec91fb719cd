// HDF5 errors as one message naming the file. HDF5 prints its whole error stack to stderr by
// default (about 600 lines on a full disk) and reports a failed write only when the file is
// closed; kiln turns automatic printing off and checks every call where it happens.
#pragma once
#include <hdf5.h>

#include <string>

namespace kiln {

// Once per process, before any other HDF5 call (every kiln HDF5 writer calls it first): turns
// HDF5's automatic error printing off, and its exit handler, which in 1.10 crashes (SIGSEGV in
// H5F__close_cb) on a file whose close failed on a full disk. kiln closes every file itself.
void h5_setup();

// Throws OutputError "cannot <what> <file>: <HDF5's innermost reason>" when status or id < 0.
herr_t h5_check(herr_t status, const char* what, const std::string& file);
hid_t h5_id(hid_t id, const char* what, const std::string& file);

}  // namespace kiln
